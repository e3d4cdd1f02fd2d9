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
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkDRRNumberParser.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

namespace itk
{
namespace
{
[[noreturn]] void
ThrowMatrixError(const std::string & message)
{
  ExceptionObject e(__FILE__, __LINE__, "DRRProjectionMatrixFileIO: " + message, ITK_LOCATION);
  throw e;
}
} // namespace

DRRProjectionMatrixFileIO::MatrixType
DRRProjectionMatrixFileIO::Read() const
{
  std::error_code error;
  if (std::filesystem::is_directory(m_FileName, error))
  {
    ThrowMatrixError("cannot read projection matrix file '" + m_FileName + "': it is a directory");
  }
  std::ifstream file(m_FileName);
  if (!file)
  {
    ThrowMatrixError("cannot open projection matrix file '" + m_FileName + "'");
  }
  return ReadFromStream(file, m_FileName);
}

DRRProjectionMatrixFileIO::MatrixType
DRRProjectionMatrixFileIO::ReadFromStream(std::istream & stream, const std::string & sourceName)
{
  std::vector<double> values;
  std::string         line;
  unsigned int        lineNumber = 0;
  while (std::getline(stream, line))
  {
    ++lineNumber;
    const std::string where = (sourceName.empty() ? "line " : sourceName + ":") + std::to_string(lineNumber) + ": ";
    std::string       text = line.substr(0, line.find('#'));
    std::replace(text.begin(), text.end(), ',', ' ');
    std::istringstream tokens(text);
    size_t             onThisLine = 0;
    for (std::string token; tokens >> token; ++onThisLine)
    {
      double value = 0.0;
      if (!DRRNumberParser::ParseFiniteNumber(token, value))
      {
        ThrowMatrixError(where + "'" + token + "' is not a finite number");
      }
      values.push_back(value);
    }
    // Rows of four, or all twelve on one line.
    if (onThisLine != 0 && onThisLine != 4 && onThisLine != 12)
    {
      ThrowMatrixError(where + "a row of a 3 x 4 projection matrix has 4 numbers, this line has " +
                       std::to_string(onThisLine));
    }
  }
  if (values.size() != 12)
  {
    ThrowMatrixError((sourceName.empty() ? std::string() : sourceName + ": ") +
                     "a 3 x 4 projection matrix has 12 numbers, found " + std::to_string(values.size()));
  }
  MatrixType matrix;
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 4; ++c)
    {
      matrix[r][c] = values[4 * r + c];
    }
  }
  return matrix;
}

void
DRRProjectionMatrixFileIO::WriteToStream(std::ostream & stream, const MatrixType & matrix)
{
  std::ostringstream text;
  text << std::setprecision(17);
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 4; ++c)
    {
      if (!std::isfinite(matrix[r][c]))
      {
        ThrowMatrixError("the matrix has a non-finite entry: the reader would refuse it");
      }
      text << (c == 0 ? "" : " ") << matrix[r][c] + 0.0; // + 0.0: no negative zero
    }
    text << '\n';
  }
  stream << text.str();
}

void
DRRProjectionMatrixFileIO::Write(const MatrixType & matrix) const
{
  std::ostringstream text;
  WriteToStream(text, matrix);
  std::ofstream file(m_FileName, std::ios::out | std::ios::trunc);
  file << text.str();
  file.close(); // a short write or a failed close (a full disk) leaves the stream failed
  if (!file)
  {
    ThrowMatrixError("cannot write projection matrix file '" + m_FileName + "'");
  }
}

void
DRRProjectionMatrixFileIO::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << m_FileName << std::endl;
}
} // namespace itk
