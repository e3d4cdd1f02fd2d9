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
#include "pbdrrOptionTable.h"

#include <cctype>
#include <map>
#include <sstream>

namespace pbdrr
{
namespace
{
/** The separators of a list given as one word: commas, and for --size also an x between the two numbers. */
std::string
ListSeparators(const std::string & flag)
{
  return flag == "--size" ? ",x" : ",";
}

/** Whether the word after a flag of several values holds them all (`--size 256,256`, `--size 256x256`). */
bool
IsList(const std::string & word, const std::string & flag)
{
  return !word.empty() && std::isdigit(static_cast<unsigned char>(word.front())) != 0 &&
         word.find_first_of(ListSeparators(flag)) != std::string::npos;
}

/** The values of a flag given as one word: the word itself for one value, else split at the list separators. */
std::vector<std::string>
SplitList(const std::string & word, size_t count, const std::string & flag)
{
  if (count == 1)
  {
    return { word };
  }
  std::vector<std::string> values;
  size_t                   begin = 0;
  for (size_t end; (end = word.find_first_of(ListSeparators(flag), begin)) != std::string::npos; begin = end + 1)
  {
    values.push_back(word.substr(begin, end - begin));
  }
  values.push_back(word.substr(begin));
  if (values.size() != count)
  {
    throw UsageError(flag + " expects " + std::to_string(count) + " value(s), got '" + word + "'");
  }
  return values;
}

/** `-vq` as `-v -q`: the single-letter flags of a word, if every one of them is a flag without a value; else none. */
std::vector<std::string>
CombinedShortFlags(const std::string & word, const std::function<bool(const std::string &)> & takesNoValue)
{
  std::vector<std::string> singles;
  if (word.size() < 3 || word[0] != '-' || word[1] == '-')
  {
    return singles;
  }
  for (size_t c = 1; c < word.size(); ++c)
  {
    const std::string single{ '-', word[c] };
    if (!takesNoValue(single))
    {
      return {};
    }
    singles.push_back(single);
  }
  return singles;
}

/** The values of the option at arguments[i] (its name, name=value or a list in one word): moves i past them. */
std::vector<std::string>
OptionValues(const std::vector<std::string> & arguments, size_t & i, const OptionText & option, size_t equals)
{
  const std::string & argument = arguments[i];
  const std::string   name = argument.substr(0, equals);
  const size_t        count = option.Values;
  if (equals != std::string::npos)
  {
    return SplitList(argument.substr(equals + 1), count, name);
  }
  if (count > 1 && i + 1 < arguments.size() && IsList(arguments[i + 1], name))
  {
    return SplitList(arguments[++i], count, name);
  }
  if (i + count >= arguments.size() && count > 0)
  {
    throw UsageError(argument + " expects " + std::to_string(count) + " value(s)");
  }
  std::vector<std::string> values(arguments.begin() + i + 1, arguments.begin() + i + 1 + count);
  i += count;
  return values;
}
} // namespace

void
ReadOptionWords(const std::vector<std::string> &                                                  arguments,
                const std::vector<const OptionText *> &                                           table,
                const std::string &                                                               unknownTail,
                const std::function<void(const OptionText &, const std::vector<std::string> &)> & apply,
                const std::function<void(const std::string &)> &                                  operand)
{
  // Every option by its name and its short form.
  std::map<std::string, const OptionText *> flags;
  for (const OptionText * option : table)
  {
    flags[option->Name] = option;
    if (!option->Short.empty())
    {
      flags[option->Short] = option;
    }
  }
  for (size_t i = 0; i < arguments.size(); ++i)
  {
    const std::string & argument = arguments[i];
    if (argument.size() <= 1 || argument[0] != '-')
    {
      operand(argument);
      continue;
    }
    const size_t equals = argument.rfind("--", 0) == 0 ? argument.find('=') : std::string::npos;
    const auto   flag = flags.find(argument.substr(0, equals));
    if (flag != flags.end() && (equals == std::string::npos || flag->second->Values > 0))
    {
      apply(*flag->second, OptionValues(arguments, i, *flag->second, equals));
      continue;
    }
    const std::vector<std::string> combined = CombinedShortFlags(argument, [&](const std::string & single) {
      const auto found = flags.find(single);
      return found != flags.end() && found->second->Values == 0;
    });
    if (combined.empty())
    {
      throw UsageError("unknown option '" + argument + "'" + unknownTail);
    }
    for (const std::string & single : combined)
    {
      apply(*flags.at(single), {});
    }
  }
}

std::string
OptionHelp(const OptionText & option, const HelpLayout & layout)
{
  // A switch shows its short form beside its name (--quiet, -q); an option with values its short form, as typed (-o).
  std::string form = option.Short.empty() ? option.Name
                     : option.Values > 0  ? option.Short
                                          : option.Name + ", " + option.Short;
  if (!option.Placeholder.empty())
  {
    form += " " + option.Placeholder;
  }
  std::string  help = option.Help;
  const size_t at = help.find("{default}");
  if (at != std::string::npos)
  {
    help.replace(at, std::string("{default}").size(), option.Default);
  }
  const size_t       indent = layout.Indent + (option.Nested ? 2 : 0);
  const size_t       column = layout.Column + (option.Nested ? 2 : 0);
  std::string        text = std::string(indent, ' ') + form;
  std::istringstream lines(help);
  std::string        line;
  bool               first = true;
  while (std::getline(lines, line))
  {
    if (first && indent + form.size() + 2 <= column)
    {
      text += std::string(column - indent - form.size(), ' ') + line + "\n";
    }
    else if (first && layout.WideOnItsLine)
    {
      text += "  " + line + "\n";
    }
    else
    {
      text += (first ? "\n" : "") + std::string(column, ' ') + line + "\n";
    }
    first = false;
  }
  if (first)
  {
    text += "\n";
  }
  return text + option.Choices;
}
} // namespace pbdrr
