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
#ifndef pbdrrLoaderText_h
#define pbdrrLoaderText_h

#include <string>
#include <vector>

namespace pbdrr
{
/** Throws std::runtime_error with `message`: how every part of the loader refuses an input (LoadVolume's callers
 * print the message as it is). */
[[noreturn]] void
Fail(const std::string & message);

/** A length for messages: 4 significant digits and the unit, e.g. "2.5 mm". */
std::string
Millimetres(double value);

/** The names (without their directories) of the first 5 files, then ", ..." if there are more: a list for messages. */
std::string
JoinNames(const std::vector<std::string> & files);
} // namespace pbdrr

#endif
