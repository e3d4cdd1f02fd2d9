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
#include "pbdrrOptionPages.h"
#include "pbdrrOptions.h"

#include <map>
#include <sstream>

namespace pbdrr
{
namespace
{
/** A cell of a Markdown table: its bars escaped. */
std::string
Cell(const std::string & text)
{
  std::string escaped;
  for (const char c : text)
  {
    escaped += c == '|' ? std::string("\\|") : std::string(1, c);
  }
  return escaped;
}

/** The row of the page of one option; counts the options each mode takes in taken. */
std::string
PageRow(const OptionDeclaration & declaration, std::map<unsigned, size_t> & taken)
{
  const std::map<OptionGroup, std::string> groups = { { OptionGroup::Geometry, "geometry" },
                                                      { OptionGroup::Rendering, "rendering" },
                                                      { OptionGroup::Physics, "physics" },
                                                      { OptionGroup::Batches, "batches" },
                                                      { OptionGroup::Messages, "messages" } };
  const auto                               mode = [&](unsigned bit) {
    taken[bit] += (declaration.Modes & bit) ? 1 : 0;
    return std::string((declaration.Modes & bit) ? "yes" : "refused");
  };
  return "| `" + declaration.Name + "`" + (declaration.Short.empty() ? "" : ", `" + declaration.Short + "`") + " | " +
         (declaration.Placeholder.empty() ? "" : "`" + Cell(declaration.Placeholder) + "`") + " | " +
         groups.at(declaration.Group) + " | " + mode(OptionModes::SingleView) + " | " + mode(OptionModes::Batch) +
         " | " + mode(OptionModes::Manifest) + " | " + Cell(declaration.Refusal) + " |\n";
}
} // namespace

std::string
OptionsPage()
{
  std::string                page = R"(# The options of pbdrr and their modes

Made from `OptionDeclarations()` (`apps/pbdrr/pbdrrOptionDeclarations.cxx`), which `pbdrr --help` prints, by
`cmake --build build --target pbdrr_option_pages`; the test `OptionDeclarations.AreTheOptionsPage` fails on any
difference. A mode an option is not declared for refuses it and writes nothing: a single view with "NAME: for a
batch of views", a batch (`--angles`, `--views`, `--rtk-geometry`) or a manifest (`--manifest`) with the message
of the last column. `--angles`, `--views` and `--rtk-geometry` make a run a batch, `--manifest` a manifest.

| option | values | group | single view | batch | manifest | refused with |
|---|---|---|---|---|---|---|
)";
  std::map<unsigned, size_t> taken; // options per mode
  for (const OptionDeclaration & declaration : OptionDeclarations())
  {
    page += PageRow(declaration, taken);
  }
  return page + "\n" + std::to_string(OptionDeclarations().size()) +
         " options: " + std::to_string(taken[OptionModes::SingleView]) + " taken by a single view, " +
         std::to_string(taken[OptionModes::Batch]) + " by a batch, " + std::to_string(taken[OptionModes::Manifest]) +
         " by a manifest.\n";
}

std::string
OptionsDictionary(const std::string & current)
{
  std::string options;
  for (const OptionDeclaration & declaration : OptionDeclarations())
  {
    for (const std::string & form : { declaration.Name, declaration.Short })
    {
      if (!form.empty())
      {
        options += "\"" + form + "\\x00\"\n";
      }
    }
  }
  std::istringstream lines(current);
  std::string        dictionary;
  bool               written = false;
  for (std::string line; std::getline(lines, line);)
  {
    if (line.rfind("\"-", 0) != 0)
    {
      dictionary += line + "\n";
    }
    else if (!written)
    {
      dictionary += options;
      written = true;
    }
  }
  return written ? dictionary : dictionary + options;
}
} // namespace pbdrr
