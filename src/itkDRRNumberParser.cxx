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
#include "itkDRRNumberParser.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace itk
{
bool
DRRNumberParser::ParseFiniteNumber(const std::string & text, double & value)
{
  const char * begin = text.c_str();
  char *       end = nullptr;
  errno = 0;
  const double number = std::strtod(begin, &end);
  if (text.empty() || end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(number))
  {
    return false;
  }
  value = number;
  return true;
}

bool
DRRNumberParser::IsWholeNumberInRange(double value, double minimum, double maximum)
{
  return value >= minimum && value <= maximum && value == std::floor(value);
}
} // namespace itk
