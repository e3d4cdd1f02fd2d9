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
// pbdrrOptionPages SOURCE_DIR: writes the files made from pbdrr's table of options into the source tree,
// docs/options.md and the option lines of test/fuzz/Options.dict (pbdrrOptionPages.h). Run by
//   cmake --build build --target pbdrr_option_pages
// after adding, renaming or moving an option; the tests OptionDeclarations.AreTheOptionsPage and AreTheFuzzDictionary
// fail until then.
#include "pbdrrOptionPages.h"

#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
bool
Write(const std::string & path, const std::string & text)
{
  std::ofstream file(path, std::ios::binary);
  file << text;
  std::cout << "pbdrrOptionPages: wrote " << path << std::endl;
  return file.good();
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: pbdrrOptionPages SOURCE_DIR (writes docs/options.md and test/fuzz/Options.dict)" << std::endl;
    return 2;
  }
  const std::string  source = argv[1];
  const std::string  dictionaryPath = source + "/test/fuzz/Options.dict";
  std::ifstream      current(dictionaryPath, std::ios::binary);
  std::ostringstream dictionary;
  dictionary << current.rdbuf();
  if (!current.good())
  {
    std::cerr << "pbdrrOptionPages: cannot read " << dictionaryPath << std::endl;
    return 1;
  }
  const bool written = Write(source + "/docs/options.md", pbdrr::OptionsPage()) &&
                       Write(dictionaryPath, pbdrr::OptionsDictionary(dictionary.str()));
  return written ? 0 : 1;
}
