/*=========================================================================
 *
 *  Copyright NumFOCUS and the PointBasedDRR contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#ifndef itkDRRTextFileReader_h
#define itkDRRTextFileReader_h

#include "itkMacro.h"

#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace itk
{
/** \class DRRTextFileReader
 * \brief The lines of a small text table (DRRMaterialTable, DRRXRaySpectrum files), split into fields.
 *
 * Fields are separated by whitespace or commas; a field in double quotes keeps its spaces and commas (a NIST material
 * name such as "Air, Dry (near sea level)"). A '#' outside quotes starts a comment to the end of the line. Blank and
 * comment-only lines are skipped; each kept line keeps its number (from 1) for error messages. Internal to the
 * library (not installed with a public API).
 * \ingroup PointBasedDRR
 */
class DRRTextFileReader
{
public:
  /** One kept line: its number in the file (from 1) and its fields. */
  using LineType = std::pair<unsigned int, std::vector<std::string>>;

  /** Reads path; what names the kind of file in the exception thrown when it cannot be opened or has an unterminated
   * quote. */
  static std::vector<LineType>
  Read(const std::string & path, const std::string & what)
  {
    std::ifstream file(path);
    if (!file)
    {
      itkGenericExceptionMacro("cannot open the " << what << " file '" << path << "'");
    }
    std::vector<LineType> lines;
    std::string           text;
    unsigned int          number = 0;
    while (std::getline(file, text))
    {
      ++number;
      std::vector<std::string> fields;
      std::string              field;
      bool                     inField = false, quoted = false;
      for (const char c : text)
      {
        if (quoted)
        {
          if (c == '"')
          {
            quoted = false;
          }
          else
          {
            field += c;
          }
          continue;
        }
        if (c == '#')
        {
          break;
        }
        if (c == '"')
        {
          quoted = true;
          inField = true;
        }
        else if (c == ',' || c == ' ' || c == '\t' || c == '\r')
        {
          if (inField)
          {
            fields.push_back(field);
          }
          field.clear();
          inField = false;
        }
        else
        {
          field += c;
          inField = true;
        }
      }
      if (quoted)
      {
        itkGenericExceptionMacro(<< what << " file '" << path << "', line " << number << ": unterminated quote");
      }
      if (inField)
      {
        fields.push_back(field);
      }
      if (!fields.empty())
      {
        lines.emplace_back(number, fields);
      }
    }
    return lines;
  }
};
} // namespace itk

#endif
