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
// The policy registries (itkDRRPolicies.h, DRRSamplerFactory) are the one list of kernels, splats, beams and
// samplers: these tests fail when a registered policy is missing from anything that must list it (the command line's
// help and parsing, the enumerators' names, the dispatch, the wrapping, docs/wrapping.md, the README, the fuzzers'
// dictionaries), or when the registrations contradict each other.
#include "pbdrrOptionPages.h"
#include "pbdrrOptions.h"

#include "itkDRRPolicies.h"
#include "itkDRRSamplerFactory.h"
#include "itkPointBasedDRRImageFilter.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace
{
std::string
ReadProjectFile(const std::string & relativePath)
{
  std::ifstream file(std::string(PBDRR_SOURCE_DIR) + "/" + relativePath);
  EXPECT_TRUE(file.good()) << relativePath;
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

/** True if the help has a line: indentation, the name, spaces, the description. */
bool
HelpLists(const std::string & help, const std::string & name, const std::string & description)
{
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);)
  {
    const size_t start = line.find_first_not_of(' ');
    if (start != std::string::npos && start > 0 && line.compare(start, name.size(), name) == 0)
    {
      const size_t text = line.find_first_not_of(' ', start + name.size());
      if (text > start + name.size() && text != std::string::npos && line.substr(text) == description)
      {
        return true;
      }
    }
  }
  return false;
}

/** The message ParseCommandLine() throws for arguments, or "" if it accepts them. */
std::string
ParseError(const std::vector<std::string> & arguments)
{
  try
  {
    pbdrr::ParseCommandLine(arguments);
  }
  catch (const pbdrr::UsageError & error)
  {
    return error.what();
  }
  return "";
}

std::string
Joined(const std::vector<std::string> & names)
{
  std::string list;
  for (const auto & name : names)
  {
    list += (list.empty() ? "" : ", ") + name;
  }
  return list;
}

/** What every compile-time registry must satisfy: unique lower-case names, a description each, printed enumerator
 * names from the registry, a dispatch that reaches the policy of each enumerator, and a command line that parses
 * every name into its enumerator and lists exactly the registered names when it refuses one. */
template <typename TPolicies>
void
CheckPolicyList(const std::string & option)
{
  std::set<std::string> names;
  const std::string     help = pbdrr::HelpText();
  for (const auto & entry : TPolicies::GetEntries())
  {
    EXPECT_TRUE(names.insert(entry.Name).second) << "duplicate name " << entry.Name;
    EXPECT_EQ(entry.Name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-"), std::string::npos) << entry.Name;
    EXPECT_FALSE(pbdrr::PolicyHelpLine(entry.Name).empty()) << entry.Name << " has no line in pbdrr's help table";
    EXPECT_EQ(TPolicies::GetName(entry.Id), entry.Name);
    EXPECT_EQ(TPolicies::Visit(entry.Id, [](auto policy) { return std::string(decltype(policy)::Name); }), entry.Name)
      << "the dispatch must reach the policy registered for the enumerator";
    std::ostringstream printed;
    printed << entry.Id;
    EXPECT_EQ(printed.str(), TPolicies::ToCamelCase(entry.Name)) << "operator<< must print the registered name";
    typename TPolicies::EnumType parsed{};
    ASSERT_TRUE(TPolicies::FindByName(entry.Name, parsed)) << entry.Name;
    EXPECT_EQ(parsed, entry.Id);
    // The public API (what pbdrr and users ask, PointBasedDRREnums) says what the registry says.
    typename TPolicies::EnumType publicParsed{};
    ASSERT_TRUE(itk::PointBasedDRREnums::FromName(entry.Name, publicParsed)) << entry.Name;
    EXPECT_EQ(publicParsed, entry.Id);
    EXPECT_EQ(itk::PointBasedDRREnums::GetName(entry.Id), entry.Name);
    if (!option.empty())
    {
      EXPECT_TRUE(HelpLists(help, entry.Name, pbdrr::PolicyHelpLine(entry.Name)))
        << "pbdrr --help must list " << entry.Name << " with its help line";
      EXPECT_EQ(ParseError({ "in.mha", "-o", "out.mha", option, entry.Name }), "") << option << " " << entry.Name;
    }
  }
  if (!option.empty())
  {
    EXPECT_EQ(ParseError({ "in.mha", "-o", "out.mha", option, "no-such-policy" }),
              option + " expects one of " + Joined(TPolicies::GetNames()) + ", got 'no-such-policy'");
  }
  EXPECT_EQ(itk::PointBasedDRREnums::GetNames<typename TPolicies::EnumType>(), TPolicies::GetNames());
  typename TPolicies::EnumType untouched = TPolicies::GetEntries().back().Id;
  EXPECT_FALSE(itk::PointBasedDRREnums::FromName("no-such-policy", untouched));
  EXPECT_EQ(untouched, TPolicies::GetEntries().back().Id) << "a name not registered leaves the value alone";
  const auto unregistered = static_cast<typename TPolicies::EnumType>(200);
  EXPECT_THROW(TPolicies::GetName(unregistered), itk::ExceptionObject);
  std::ostringstream printed;
  printed << unregistered;
  EXPECT_EQ(printed.str(), "INVALID") << "an unregistered enumerator must not print as a registered one";
}
} // namespace

TEST(PolicyRegistry, KernelsAreRegisteredOnceAndListedEverywhere)
{
  CheckPolicyList<itk::DRRPolicies::Kernels>("--kernel");
}

TEST(PolicyRegistry, SplatsAreRegisteredOnceAndListedEverywhere)
{
  CheckPolicyList<itk::DRRPolicies::Splats>("--splat");
}

TEST(PolicyRegistry, BeamsAreRegisteredOnce)
{
  CheckPolicyList<itk::DRRPolicies::Beams>("");
}

TEST(PolicyRegistry, BeamsSayWhetherTheyHaveASource)
{
  for (const auto & entry : itk::DRRPolicies::Beams::GetEntries())
  {
    EXPECT_EQ(itk::PointBasedDRREnums::HasSource(entry.Id),
              itk::DRRPolicies::Beams::Visit(entry.Id, [](auto beam) { return decltype(beam)::HasSource; }))
      << entry.Name;
  }
  EXPECT_FALSE(itk::PointBasedDRREnums::HasSource(itk::PointBasedDRREnums::Projection::Parallel));
}

TEST(PolicyRegistry, EveryExactReferenceIsOfferedByExact)
{
  std::vector<std::string> references;
  for (const auto & entry : itk::DRRPolicies::Kernels::GetEntries())
  {
    const std::string reference = pbdrr::ExactReferenceName(entry.Id);
    EXPECT_EQ(itk::PointBasedDRREnums::GetExactReferenceName(entry.Id),
              itk::DRRPolicies::Kernels::Visit(
                entry.Id,
                [](auto kernel) {
                  return std::string(decltype(kernel)::ExactReference ? decltype(kernel)::ExactReference : "");
                }))
      << entry.Name;
    if (!reference.empty())
    {
      references.push_back(reference);
      const auto options = pbdrr::ParseCommandLine({ "in.mha", "-o", "out.mha", "--exact", reference });
      ASSERT_TRUE(options.exact.has_value());
      EXPECT_EQ(*options.exact, entry.Id) << reference;
    }
  }
  EXPECT_FALSE(references.empty());
  EXPECT_EQ(ParseError({ "in.mha", "-o", "out.mha", "--exact", "foo" }),
            "--exact expects one of " + Joined(references) + ", got 'foo'");
}

TEST(PolicyRegistry, SamplersAreRegisteredOnceAndListedEverywhere)
{
  const std::string        help = pbdrr::HelpText();
  const std::string        readme = ReadProjectFile("README.md");
  const std::string        wrappingDoc = ReadProjectFile("docs/wrapping.md");
  const std::string        optionsDictionary = ReadProjectFile("test/fuzz/Options.dict");
  const std::string        filterSeeds = ReadProjectFile("test/fuzz/corpus/make_filter_seeds.py");
  std::set<std::string>    names;
  std::vector<std::string> quoted;
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    EXPECT_TRUE(names.insert(entry.Name).second) << "duplicate sampler " << entry.Name;
    const auto sampler = itk::DRRSamplerFactory::Create(entry.Name);
    ASSERT_NE(sampler, nullptr) << entry.Name;
    const std::string className = sampler->GetNameOfClass();
    EXPECT_FALSE(pbdrr::PolicyHelpLine(entry.Name).empty()) << entry.Name << " has no line in pbdrr's help table";
    EXPECT_TRUE(HelpLists(help, entry.Name, pbdrr::PolicyHelpLine(entry.Name)))
      << "pbdrr --help must list " << entry.Name;
    EXPECT_EQ(ParseError({ "in.mha", "-o", "out.mha", "--sampler", entry.Name }), "") << entry.Name;
    EXPECT_NE(readme.find("| `" + entry.Name + "`"), std::string::npos)
      << "the README's sampler table needs a row for " << entry.Name;
    EXPECT_TRUE(std::ifstream(std::string(PBDRR_SOURCE_DIR) + "/wrapping/itk" + className + ".wrap").good())
      << entry.Name << ": wrapping/itk" << className << ".wrap is missing";
    EXPECT_NE(wrappingDoc.find("`itk::" + className + "`"), std::string::npos)
      << "docs/wrapping.md must list itk::" << className;
    EXPECT_NE(optionsDictionary.find("\"" + entry.Name + "\\x00\""), std::string::npos)
      << "test/fuzz/Options.dict must hold " << entry.Name;
    quoted.push_back("\"" + entry.Name + "\"");
    if (entry.CreatePaperVariant)
    {
      EXPECT_STREQ(entry.CreatePaperVariant()->GetNameOfClass(), className.c_str()) << entry.Name;
    }
  }
  // The filter fuzzer decodes a sampler as its index in the registry: the committed seeds were made with the list in
  // the seed generator, which must be the registry's first entries in the same order (new samplers go at the end).
  const size_t listStart = filterSeeds.find("SAMPLERS = [");
  ASSERT_NE(listStart, std::string::npos) << "test/fuzz/corpus/make_filter_seeds.py has no SAMPLERS list";
  const std::string generatorList =
    filterSeeds.substr(listStart + 12, filterSeeds.find(']', listStart) - listStart - 12);
  EXPECT_EQ(Joined(quoted).compare(0, generatorList.size(), generatorList), 0)
    << "test/fuzz/corpus/make_filter_seeds.py: SAMPLERS [" << generatorList
    << "] must be the first entries of the registry, in order: " << Joined(quoted);
  EXPECT_EQ(ParseError({ "in.mha", "-o", "out.mha", "--sampler", "foo" }),
            "--sampler expects one of " + itk::DRRSamplerFactory::GetNames() + ", got 'foo'");
}

TEST(PolicyRegistry, EveryHelpLineIsOfARegisteredPolicy)
{
  // The library registers a policy once, with its name; pbdrr attaches its help line by that name. A line whose name
  // no registry holds (a renamed or removed policy) is stale.
  std::set<std::string> registered;
  for (const auto & name : itk::DRRPolicies::Kernels::GetNames())
  {
    registered.insert(name);
  }
  for (const auto & name : itk::DRRPolicies::Splats::GetNames())
  {
    registered.insert(name);
  }
  for (const auto & name : itk::DRRPolicies::Beams::GetNames())
  {
    registered.insert(name);
  }
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    registered.insert(entry.Name);
  }
  for (const auto & name : pbdrr::PolicyHelpNames())
  {
    EXPECT_EQ(registered.count(name), 1u) << "pbdrr's help table describes '" << name << "', which no registry holds";
  }
  EXPECT_EQ(pbdrr::PolicyHelpNames().size(), registered.size());
  EXPECT_EQ(pbdrr::PolicyHelpLine("no-such-policy"), "");
}

TEST(PolicyRegistry, KernelsAndSplatsAreInTheFuzzDictionaryAndTheReadme)
{
  const std::string readme = ReadProjectFile("README.md");
  const std::string optionsDictionary = ReadProjectFile("test/fuzz/Options.dict");
  for (const auto & name : itk::DRRPolicies::Kernels::GetNames())
  {
    EXPECT_NE(optionsDictionary.find("\"" + name + "\\x00\""), std::string::npos) << name;
    EXPECT_NE(readme.find(name), std::string::npos) << "the README does not name the kernel " << name;
  }
  for (const auto & name : itk::DRRPolicies::Splats::GetNames())
  {
    EXPECT_NE(optionsDictionary.find("\"" + name + "\\x00\""), std::string::npos) << name;
    EXPECT_NE(readme.find(name), std::string::npos) << "the README does not name the splat " << name;
  }
}

TEST(PolicyRegistry, TheDefaultsAreTheSameEverywhere)
{
  const pbdrr::Options defaults;
  EXPECT_EQ(defaults.kernel, itk::DRRPolicies::Kernels::GetEntries().front().Id);
  EXPECT_EQ(defaults.splat, itk::DRRPolicies::Splats::GetEntries().front().Id);
  EXPECT_EQ(defaults.sampler, itk::DRRSamplerFactory::DefaultName);
  using FilterType = itk::PointBasedDRRImageFilter<itk::Image<float, 3>, itk::Image<float, 2>>;
  EXPECT_STREQ(FilterType::New()->GetSampler()->GetNameOfClass(),
               itk::DRRSamplerFactory::Create(itk::DRRSamplerFactory::DefaultName)->GetNameOfClass());
  EXPECT_FALSE(defaults.projection.has_value()); // the geometry's own default beam, the first registered
  EXPECT_EQ(itk::DRRProjectionGeometry::New()->GetProjection(), itk::DRRPolicies::Beams::GetEntries().front().Id);
  EXPECT_EQ(itk::DRRPolicies::Beams::GetEntries().front().Id, itk::PointBasedDRREnums::Projection::Perspective);
}

TEST(PolicyRegistry, TheControlVariateIsTheFiltersToResolveAndRefuse)
{
  const auto parsed = [](std::vector<std::string> extra) {
    std::vector<std::string> arguments{ "in.mha", "-o", "out.mha" };
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return pbdrr::ParseCommandLine(arguments).controlVariate;
  };
  EXPECT_EQ(parsed({}), itk::DRRControlVariate::AutomaticFactor);
  EXPECT_EQ(parsed({ "--sampler", "level-alias" }), itk::DRRControlVariate::AutomaticFactor);
  EXPECT_EQ(parsed({ "--control-variate", "off" }), 0u);
  // The command line does not restate the filter's rules: `auto` stays auto, which the filter resolves to off where
  // the control variate does not apply (DRRPointRenderSession::ControlVariateApplies()), and a chosen F there is the
  // filter's to refuse (VerifySettings(), asked before the load).
  EXPECT_EQ(parsed({ "--kernel", "tent" }), itk::DRRControlVariate::AutomaticFactor);
  EXPECT_EQ(parsed({ "--paper-count" }), itk::DRRControlVariate::AutomaticFactor);
  EXPECT_EQ(parsed({ "--control-variate", "4", "--kernel", "tent" }), 4u);
  // An option for point sampling with the exact projector is the command line's own refusal, auto as well as F.
  EXPECT_EQ(ParseError({ "in.mha", "-o", "out.mha", "--control-variate", "auto", "--exact", "siddon" }),
            "--control-variate applies to point sampling, not to --exact");
  EXPECT_EQ(parsed({ "--exact", "siddon" }), itk::DRRControlVariate::AutomaticFactor); // not given: unused
}

// One declaration per option (issue 28): its help is made from it, each part declared (a help line, a placeholder for
// its values, the default its help states), and pbdrr --help lists it, its short form too, in lines that fit.
TEST(OptionDeclarations, EachHasItsHelp)
{
  const std::string     help = pbdrr::HelpText();
  std::set<std::string> names;
  for (const pbdrr::OptionDeclaration & declaration : pbdrr::OptionDeclarations())
  {
    EXPECT_TRUE(names.insert(declaration.Name).second) << declaration.Name << " is declared twice";
    EXPECT_EQ(declaration.Name.rfind("--", 0), 0u) << declaration.Name;
    EXPECT_TRUE(declaration.Modes & pbdrr::OptionModes::Every) << declaration.Name << " applies to no mode";
    EXPECT_FALSE(declaration.Help.empty()) << declaration.Name << " is declared without its help";
    EXPECT_FALSE(!declaration.Help.empty() && declaration.Help.back() == '\n')
      << declaration.Name << ": its help ends with an empty line";
    EXPECT_EQ(declaration.Placeholder.empty(), declaration.Values == 0)
      << declaration.Name << ": an option with values names them in the help (Placeholder), a switch does not";
    EXPECT_EQ(declaration.Default.empty(), declaration.Help.find("{default}") == std::string::npos)
      << declaration.Name << ": a declared Default is stated in its help as {default}, and only then";
    for (const std::string & form : { declaration.Name, declaration.Short })
    {
      if (form.empty() || form == "--output") // --output is -o's long form, which the help does not repeat
      {
        continue;
      }
      EXPECT_TRUE(help.find("  " + form) != std::string::npos || help.find(", " + form) != std::string::npos)
        << "pbdrr --help must list " << form;
    }
  }
  std::istringstream lines(help);
  std::string        line;
  while (std::getline(lines, line))
  {
    EXPECT_LE(line.size(), 120u) << "a line of pbdrr --help is wider than 120 columns: " << line;
    EXPECT_EQ(line.find("{default}"), std::string::npos) << line;
  }
}

// The fuzzers' dictionary of the command line holds the options of the table, in its order, each followed by its
// short form: its lines that start with a dash are exactly these (the values after them are kept by hand).
TEST(OptionDeclarations, AreTheFuzzDictionary)
{
  const std::string dictionary = ReadProjectFile("test/fuzz/Options.dict");
  EXPECT_EQ(dictionary, pbdrr::OptionsDictionary(dictionary))
    << "test/fuzz/Options.dict must list the options of OptionDeclarations(), in order: write it with\n"
       "  cmake --build build --target pbdrr_option_pages";
}

// docs/options.md, the list of every option with its modes, is the table's (pbdrr::OptionsPage()), compared whole.
TEST(OptionDeclarations, AreTheOptionsPage)
{
  EXPECT_EQ(ReadProjectFile("docs/options.md"), pbdrr::OptionsPage())
    << "docs/options.md must be the table of OptionDeclarations(): write it with\n"
       "  cmake --build build --target pbdrr_option_pages";
}
