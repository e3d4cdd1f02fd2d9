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
#include "pbdrrLoaderText.h"

#include <sstream>
#include <stdexcept>

namespace pbdrr
{
void
Fail(const std::string & message)
{
  throw std::runtime_error(message);
}

std::string
Millimetres(double value)
{
  std::ostringstream s;
  s.precision(4);
  s << value << " mm";
  return s.str();
}

std::string
JoinNames(const std::vector<std::string> & files)
{
  std::string list;
  for (size_t i = 0; i < files.size() && i < 5; ++i)
  {
    list += (i ? ", " : "") + files[i].substr(files[i].find_last_of('/') + 1);
  }
  return files.size() > 5 ? list + ", ..." : list;
}
} // namespace pbdrr
