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
#ifndef pbdrrOptionPages_h
#define pbdrrOptionPages_h

// The files made from pbdrr's table of options (OptionDeclarations()), so that an option is declared in one place:
// docs/options.md and the option lines of the fuzzers' dictionary test/fuzz/Options.dict. The program
// pbdrrOptionPages writes them (cmake --build build --target pbdrr_option_pages); the tests
// OptionDeclarations.AreTheOptionsPage and AreTheFuzzDictionary fail when the committed files differ.

#include <string>

namespace pbdrr
{
/** docs/options.md: every option of pbdrr with its values, its group, the modes it applies to and the refusal of the
 * others. */
std::string
OptionsPage();

/** test/fuzz/Options.dict as it should be, given its text now: its lines that start with a dash replaced, where the
 * first of them is, by the table's options in its order, each followed by its short form; its other lines (the
 * comments, the values kept by hand) as they are. */
std::string
OptionsDictionary(const std::string & current);
} // namespace pbdrr

#endif
