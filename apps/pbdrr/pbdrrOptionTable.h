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
#ifndef pbdrrOptionTable_h
#define pbdrrOptionTable_h

// The machinery of a command's table of options, shared by pbdrr (OptionDeclarations()) and pbdrr register
// (RegisterOptionDeclarations()): an option is declared once, in a line or a few, with named fields,
//   Option("--sad").In(Geometry).Takes("MM").Default("1000").Help("...").Sets(&Options::sad, Length("SAD"))
// and the same code parses it (ParseOptionTable()) and prints its help (OptionHelp()). As RTK's .ggo files do for
// gengetopt, without a generator: the table is C++.

#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace pbdrr
{
/** A command-line error: printed as "pbdrr: error: <what>", exit code 2 (usage) or 1 (run time). */
class UsageError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** The modes of pbdrr an option applies to (OptionDeclaration::Modes): a bit each. */
namespace OptionModes
{
/** pbdrr INPUT -o OUTPUT: one view. */
constexpr unsigned SingleView = 1u;
/** --angles, --views or --rtk-geometry: a batch of views of one volume. */
constexpr unsigned Batch = 2u;
/** --manifest: batches of many volumes. */
constexpr unsigned Manifest = 4u;
/** Every mode. */
constexpr unsigned Every = SingleView | Batch | Manifest;
} // namespace OptionModes

/** What the help and the parser read of an option, whatever the command: its names, its values and its text. */
struct OptionText
{
  std::string Name;                        ///< --name
  std::string Short;                       ///< -x, or empty
  size_t      Values{ 0 };                 ///< how many values follow it (0: a switch): the words of Placeholder
  unsigned    Modes{ OptionModes::Every }; ///< the modes it applies to (OptionModes bits)
  /** Why a batch or a manifest that it does not apply to refuses it (a single view says "for a batch of views"). */
  std::string Refusal;
  /** Its values in the help, named with their unit where they have one (MM, DEG, KEV, PER_MM, HU, KV), or the words it
   * takes (F|auto|off, hu|mu); empty for a switch. */
  std::string Placeholder;
  /** The default the help states, where it states one: {default} in Help stands for it; empty otherwise. */
  std::string Default;
  /** Its help: one or more lines separated by '\n', printed as they break here, in the column of the help. */
  std::string Help;
  /** Lines printed under Help as they are: the names it takes, from their registry (--kernel, --exact, ...), a note;
   * or empty. */
  std::string Choices{};
  /** Printed two columns further in, as a part of the option above it (register's --geometry under --xray). */
  bool Nested{ false };
};

/** One option of a command (TOptions: what its command line says; TGroup: the groups of its help). */
template <typename TOptions, typename TGroup>
struct OptionDeclarationOf : OptionText
{
  TGroup Group{}; ///< the group of the help it is shown in
  /** Sets the option in options from its values; throws UsageError naming it and a bad value. */
  std::function<void(TOptions &, const std::vector<std::string> &)> Apply;
};

/** Declares an option by named fields (OptionDeclarationOf), each said once; a command's table aliases it:
 *   using Option = OptionBuilder<Options, OptionGroup>;
 *   Option("--seed").In(Rendering).Takes("S").Default("0").Help("random seed (default {default})").Sets(...)
 * The number of values is the number of words of Takes(); Only() narrows the modes (and says why the others refuse
 * it); Sets() stores into a field (a switch sets a bool, a FILE a string, else what a parser of the value returns);
 * Does() runs anything else. */
template <typename TOptions, typename TGroup>
class OptionBuilder
{
public:
  using Declaration = OptionDeclarationOf<TOptions, TGroup>;
  using Values = std::vector<std::string>;

  explicit OptionBuilder(std::string name) { m_Declaration.Name = std::move(name); }

  OptionBuilder &&
  Short(std::string form) &&
  {
    m_Declaration.Short = std::move(form);
    return std::move(*this);
  }
  OptionBuilder &&
  In(TGroup group) &&
  {
    m_Declaration.Group = group;
    return std::move(*this);
  }
  /** Its values as the help names them: a word per value ("X Y Z": three values). */
  OptionBuilder &&
  Takes(std::string placeholder) &&
  {
    m_Declaration.Values = WordCount(placeholder);
    m_Declaration.Placeholder = std::move(placeholder);
    return std::move(*this);
  }
  OptionBuilder &&
  Default(std::string value) &&
  {
    m_Declaration.Default = std::move(value);
    return std::move(*this);
  }
  OptionBuilder &&
  Help(std::string text) &&
  {
    m_Declaration.Help = std::move(text);
    return std::move(*this);
  }
  /** Lines printed under the help as they are (the names a policy option takes). */
  OptionBuilder &&
  Choices(std::string lines) &&
  {
    m_Declaration.Choices = std::move(lines);
    return std::move(*this);
  }
  /** The modes it applies to (OptionModes bits), and the refusal of a batch or a manifest it does not apply to. */
  OptionBuilder &&
  Only(unsigned modes, std::string refusal = "") &&
  {
    m_Declaration.Modes = modes;
    m_Declaration.Refusal = std::move(refusal);
    return std::move(*this);
  }
  OptionBuilder &&
  Nested() &&
  {
    m_Declaration.Nested = true;
    return std::move(*this);
  }
  /** What it does with its values. */
  OptionBuilder &&
  Does(std::function<void(TOptions &, const Values &)> apply) &&
  {
    m_Declaration.Apply = std::move(apply);
    return std::move(*this);
  }
  /** A switch: sets the field true. */
  OptionBuilder &&
  Sets(bool TOptions::*field) &&
  {
    return std::move(*this).Does([field](TOptions & options, const Values &) { options.*field = true; });
  }
  /** A word as it is (a file name, a UID): the field is it. */
  OptionBuilder &&
  Sets(std::string TOptions::*field) &&
  {
    return std::move(*this).Does([field](TOptions & options, const Values & values) { options.*field = values[0]; });
  }
  /** The field is what parse returns, called (value) or (value, name) for one value, (values, name) for several. */
  template <typename TField, typename TParse>
  OptionBuilder &&
  Sets(TField TOptions::*field, TParse parse) &&
  {
    const std::string name = m_Declaration.Name;
    return std::move(*this).Does([field, parse, name](TOptions & options, const Values & values) {
      if constexpr (std::is_invocable_v<TParse, const Values &, const std::string &>)
      {
        options.*field = parse(values, name);
      }
      else if constexpr (std::is_invocable_v<TParse, const std::string &, const std::string &>)
      {
        options.*field = parse(values[0], name);
      }
      else
      {
        options.*field = parse(values[0]);
      }
    });
  }

  operator Declaration() && { return std::move(m_Declaration); }

private:
  static size_t
  WordCount(const std::string & text)
  {
    size_t words = 0;
    for (size_t c = 0; c < text.size(); ++c)
    {
      words += text[c] != ' ' && (c == 0 || text[c - 1] == ' ') ? 1 : 0;
    }
    return words;
  }

  Declaration m_Declaration;
};

/** Reads a command line by a table of options, calling apply(option, its values) for each option in order and
 * operand(word) for each other word. The forms people type: --name value..., --name=value (lists as 1,2 or, for
 * --size, 256x256), a list as one word, -vq for -v -q. Throws UsageError "unknown option 'WORD'" + unknownTail, or
 * "WORD expects N value(s)". */
void
ReadOptionWords(const std::vector<std::string> &                                                  arguments,
                const std::vector<const OptionText *> &                                           table,
                const std::string &                                                               unknownTail,
                const std::function<void(const OptionText &, const std::vector<std::string> &)> & apply,
                const std::function<void(const std::string &)> &                                  operand);

/** Parses arguments into options by the table: each option's Apply, in the order given, and operand(word) for each
 * other word; adds the long names of the options given to given. */
template <typename TOptions, typename TGroup>
void
ParseOptionTable(const std::vector<std::string> &                           arguments,
                 const std::vector<OptionDeclarationOf<TOptions, TGroup>> & table,
                 const std::string &                                        unknownTail,
                 TOptions &                                                 options,
                 std::vector<std::string> &                                 given,
                 const std::function<void(const std::string &)> &           operand)
{
  std::vector<const OptionText *> texts;
  for (const auto & declaration : table)
  {
    texts.push_back(&declaration);
  }
  const auto apply = [&](const OptionText & option, const std::vector<std::string> & values) {
    // option is one of table's declarations (texts points into table).
    static_cast<const OptionDeclarationOf<TOptions, TGroup> &>(option).Apply(options, values);
    given.push_back(option.Name);
  };
  ReadOptionWords(arguments, texts, unknownTail, apply, operand);
}

/** Where a help's columns are: its options' forms start at Indent, their help at Column (a nested option's 2 further
 * in); a form too wide for its column puts the help on the next line, or with WideOnItsLine after two spaces. */
struct HelpLayout
{
  size_t Indent{ 2 };
  size_t Column{ 25 };
  bool   WideOnItsLine{ false };
};

/** The help of one option: its form (--name, -o, --quiet, -q) and placeholder, then its help, its lines as declared,
 * with {default} its Default, then its Choices. */
std::string
OptionHelp(const OptionText & option, const HelpLayout & layout = {});

/** The help of a group's options, in the table's order. */
template <typename TOptions, typename TGroup>
std::string
GroupHelp(const std::vector<OptionDeclarationOf<TOptions, TGroup>> & table,
          TGroup                                                     group,
          const HelpLayout &                                         layout = {})
{
  std::string text;
  for (const auto & declaration : table)
  {
    if (declaration.Group == group)
    {
      text += OptionHelp(declaration, layout);
    }
  }
  return text;
}
} // namespace pbdrr

#endif
