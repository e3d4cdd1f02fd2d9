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
// The parsers of pbdrr's option values (OptionDeclarations() calls them): each refuses a bad value with a UsageError
// that names the option and the value.
#include "pbdrrOptionValues.h"
#include "pbdrrMessages.h"
#include "itkDRRControlVariate.h"
#include "itkDRRNumberParser.h"
#include "itkDRRSamplerFactory.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pbdrr
{
[[noreturn]] void
ThrowNotOneOf(const std::string & value, const std::string & flag, const std::vector<std::string> & allowed)
{
  throw UsageError(flag + " expects one of " + JoinWords(allowed, ", ") + ", got '" + value + "'");
}

std::string
OneOf(const std::string & value, const std::string & flag, const std::vector<std::string> & allowed)
{
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
  {
    ThrowNotOneOf(value, flag, allowed);
  }
  return value;
}

/** --exact NAME: the kernel whose exact projector is called NAME (DRRBoxKernel::ExactReference). */
itk::PointBasedDRREnums::ReconstructionKernel
ExactReferenceKernel(const std::string & value)
{
  std::vector<std::string> references;
  for (const std::string & name : itk::PointBasedDRREnums::GetNames<itk::PointBasedDRREnums::ReconstructionKernel>())
  {
    itk::PointBasedDRREnums::ReconstructionKernel kernel{};
    itk::PointBasedDRREnums::FromName(name, kernel);
    const std::string reference = itk::PointBasedDRREnums::GetExactReferenceName(kernel);
    if (reference == value)
    {
      return kernel;
    }
    if (!reference.empty())
    {
      references.push_back(reference);
    }
  }
  ThrowNotOneOf(value, "--exact", references);
}

/** A length in mm within what a radiograph can mean: 1 nm to 10 km. */
double
PositiveLength(const std::string & value, const std::string & flag, const std::string & name)
{
  const double length = ParseNumber(value, flag);
  if (!(length >= 1e-6 && length <= 1e7))
  {
    throw UsageError(flag + ": the " + name + " must be a positive length in mm (1e-6 to 1e7), got '" + value + "'");
  }
  return length;
}

std::vector<std::string>
SamplerNames()
{
  std::vector<std::string> names;
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    names.push_back(entry.Name);
  }
  return names;
}

unsigned
WholeNumber(const std::string & value, const std::string & flag, double lowest, double highest)
{
  const double number = ParseNumber(value, flag);
  if (number != std::floor(number) || number < lowest || number > highest)
  {
    throw UsageError(flag + " expects a whole number from " + std::to_string(static_cast<long long>(lowest)) + " to " +
                     std::to_string(static_cast<long long>(highest)) + ", got '" + value + "'");
  }
  return static_cast<unsigned>(number);
}

/** A size in bytes: a number with an optional unit K, M, G or T (powers of 1024, optionally followed by B or iB), or
 * B; 0 for none. */
uint64_t
ParseByteSize(const std::string & value, const std::string & flag)
{
  size_t unitStart = value.find_first_not_of("0123456789.eE+-");
  // An exponent's e is part of the number only when followed by a digit or a sign ("1e9"), not in "1E" (no unit E).
  const std::string number = value.substr(0, unitStart);
  std::string       unit = unitStart == std::string::npos ? std::string() : value.substr(unitStart);
  for (char & c : unit)
  {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  const std::vector<std::pair<std::string, double>> units = { { "", 1.0 },      { "B", 1.0 },      { "K", 0x1p10 },
                                                              { "KB", 0x1p10 }, { "KIB", 0x1p10 }, { "M", 0x1p20 },
                                                              { "MB", 0x1p20 }, { "MIB", 0x1p20 }, { "G", 0x1p30 },
                                                              { "GB", 0x1p30 }, { "GIB", 0x1p30 }, { "T", 0x1p40 },
                                                              { "TB", 0x1p40 }, { "TIB", 0x1p40 } };
  const auto                                        found =
    std::find_if(units.begin(), units.end(), [&](const std::pair<std::string, double> & u) { return u.first == unit; });
  if (number.empty() || found == units.end())
  {
    throw UsageError(flag + " expects a size such as 3G, 512M or 0 (none), got '" + value + "'");
  }
  const double bytes = ParseNumber(number, flag) * found->second;
  if (!(bytes >= 0.0 && bytes <= 0x1p62))
  {
    throw UsageError(flag + " expects a size from 0 to 4 EiB, got '" + value + "'");
  }
  return static_cast<uint64_t>(bytes);
}

/** "1,3,7" (--keep-labels, --drop-labels): labels from 0 to 65535, each once. */
std::vector<uint16_t>
ParseLabelList(const std::string & value, const std::string & flag)
{
  std::vector<uint16_t> labels;
  std::stringstream     words(value);
  std::string           word;
  while (std::getline(words, word, ','))
  {
    const bool digits = !word.empty() && word.size() <= 5 && std::all_of(word.begin(), word.end(), ::isdigit);
    if (!digits || std::stol(word) > 65535)
    {
      throw UsageError(flag + " expects labels from 0 to 65535 separated by commas (1,3,7), got '" + value + "'");
    }
    const auto label = static_cast<uint16_t>(std::stol(word));
    if (std::count(labels.begin(), labels.end(), label))
    {
      throw UsageError(flag + " lists label " + word + " twice");
    }
    labels.push_back(label);
  }
  if (labels.empty() || value.back() == ',')
  {
    throw UsageError(flag + " expects labels from 0 to 65535 separated by commas (1,3,7), got '" + value + "'");
  }
  return labels;
}

/** --shard K/N: shard K (0 .. N - 1) of N. */
std::array<unsigned, 2>
ParseShard(const std::string & value)
{
  const size_t slash = value.find('/');
  if (slash == std::string::npos)
  {
    throw UsageError("--shard expects K/N (shard K of N, K from 0 to N - 1), got '" + value + "'");
  }
  const unsigned count = WholeNumber(value.substr(slash + 1), "--shard N", 1, 1000000);
  const unsigned index = WholeNumber(value.substr(0, slash), "--shard K", 0, 1000000);
  if (index >= count)
  {
    throw UsageError("--shard " + value + ": K must be below N (shards are numbered 0 to N - 1)");
  }
  return { index, count };
}

/** --control-variate F|auto|off: the filter's factor (0 off, AutomaticControlVariateFactor for auto). */
unsigned
ControlVariateFactor(const std::string & value)
{
  if (value == "off")
  {
    return 0;
  }
  if (value == "auto")
  {
    return itk::DRRControlVariate::AutomaticFactor;
  }
  if (!value.empty() && (std::isdigit(static_cast<unsigned char>(value[0])) || value[0] == '+' || value[0] == '.'))
  {
    return WholeNumber(value, "--control-variate", 2, itk::DRRControlVariate::MaximumFactor);
  }
  throw UsageError("--control-variate expects off, auto or a coarsening factor from 2 to " +
                   std::to_string(itk::DRRControlVariate::MaximumFactor) + ", got '" + value + "'");
}
} // namespace pbdrr
