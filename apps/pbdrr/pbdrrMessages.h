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
#ifndef pbdrrMessages_h
#define pbdrrMessages_h

#include <string>
#include <vector>

namespace pbdrr
{
/** An ITK message without its machinery: no "ITK ERROR:", source file and line, or "Class (0x...):" prefix. */
std::string
CleanMessage(const std::string & message);

/** A number as iostream prints it by default (6 significant digits). */
std::string
FormatNumber(double value);

/** A geometry number as a person reads it: rounded to 1e-9 (6.12323e-17 is 0) and without a negative zero. */
double
RoundedForDisplay(double value);

/** "[x, y, z]" of the first three components of a point or vector, each RoundedForDisplay(). */
template <typename TTriple>
std::string
FormatTriple(const TTriple & triple)
{
  return "[" + FormatNumber(RoundedForDisplay(triple[0])) + ", " + FormatNumber(RoundedForDisplay(triple[1])) + ", " +
         FormatNumber(RoundedForDisplay(triple[2])) + "]";
}

/** s in lower case (ASCII). */
std::string
Lowercase(std::string s);

/** True if s ends with suffix. */
bool
EndsWith(const std::string & s, const std::string & suffix);

/** The words joined by separator ("a, b, c"). */
std::string
JoinWords(const std::vector<std::string> & words, const std::string & separator);

/** Routes ITK warnings to stderr as "pbdrr: warning: ..." (cleaned), or nowhere when quiet. */
void
InstallMessageWindow();
void
SetQuietMessages(bool quiet);
} // namespace pbdrr

#endif
