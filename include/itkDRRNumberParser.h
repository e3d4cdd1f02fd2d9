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
#ifndef itkDRRNumberParser_h
#define itkDRRNumberParser_h

#include "PointBasedDRRExport.h"

#include <string>

namespace itk
{
/** \class DRRNumberParser
 * \brief The strict number parsing of the module's text inputs: the geometry file and the pbdrr command line.
 *
 * A number is a token that std::strtod() reads whole (decimal, exponent, hexadecimal float; leading white space is
 * skipped by strtod, trailing characters are refused), that is finite, and whose conversion neither overflows nor
 * underflows (strtod's ERANGE). "inf", "nan", "1e999", "1e-320", "12mm", "" and " " are refused. The callers keep
 * their own error messages: ParseFiniteNumber() only answers whether the text is a number.
 *
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRNumberParser
{
public:
  /** Parses the whole of text as a finite number. Returns false, leaving value unchanged, if text is not one. */
  static bool
  ParseFiniteNumber(const std::string & text, double & value);

  /** True if value is a whole number from minimum to maximum (both included). */
  static bool
  IsWholeNumberInRange(double value, double minimum, double maximum);
};
} // namespace itk

#endif
