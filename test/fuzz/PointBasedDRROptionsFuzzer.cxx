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

// libFuzzer target: the bytes are a pbdrr command line (arguments separated by NUL or white space), given to
// pbdrr::ParseCommandLine() (docs/fuzzing.md). Only pbdrr::UsageError and itk::ExceptionObject may escape; any other
// exception, a crash or a sanitizer report is a finding (abort). An accepted command line must also hold what the
// parser promises: an input and an output (unless --help, --version or --list-series ROOT; neither with --manifest),
// finite numbers, whole sample counts in [1, 2^40], lengths within [1e-6, 1e7] mm, a shard K below N.

#include "pbdrrOptions.h"
#include "itkMacro.h"
#include "itkObject.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace
{
[[noreturn]] void
Finding(const std::string & what, const std::vector<std::string> & arguments)
{
  std::cerr << "PointBasedDRROptionsFuzzer finding: " << what << "\narguments (" << arguments.size() << "):";
  for (const auto & a : arguments)
  {
    std::cerr << " '" << a << "'";
  }
  std::cerr << std::endl;
  std::abort();
}

std::vector<std::string>
SplitArguments(const uint8_t * data, size_t size)
{
  std::vector<std::string> arguments;
  std::string              current;
  for (size_t i = 0; i < size; ++i)
  {
    const char c = static_cast<char>(data[i]);
    if (c == '\0' || c == ' ' || c == '\t' || c == '\n' || c == '\r')
    {
      if (!current.empty())
      {
        arguments.push_back(current);
        current.clear();
      }
    }
    else
    {
      current += c;
    }
  }
  if (!current.empty())
  {
    arguments.push_back(current);
  }
  return arguments;
}

template <size_t N>
bool
Finite(const std::optional<std::array<double, N>> & values)
{
  if (!values)
  {
    return true;
  }
  for (const double v : *values)
  {
    if (!std::isfinite(v))
    {
      return false;
    }
  }
  return true;
}

bool
Finite(const std::optional<double> & value)
{
  return !value || std::isfinite(*value);
}

bool
Length(const std::optional<double> & value)
{
  return !value || (*value >= 1e-6 && *value <= 1e7);
}

void
CheckAccepted(const pbdrr::Options & o, const std::vector<std::string> & arguments)
{
  const auto check = [&](bool ok, const char * what) {
    if (!ok)
    {
      Finding(std::string("ParseCommandLine() accepted a command line whose ") + what, arguments);
    }
  };
  if (!o.help && !o.version && o.listSeries.empty() && o.manifest.empty())
  {
    check(!o.input.empty() && !o.output.empty(), "input or output is empty");
    check(!(o.energyKeV && o.muWater), "energy and mu-water are both set");
  }
  if (!o.manifest.empty() && !o.help && !o.version && o.listSeries.empty())
  {
    check(o.input.empty() && o.output.empty(), "a manifest run has an input or an output of its own");
  }
  check(!o.shard || (*o.shard)[0] < (*o.shard)[1], "shard K is not below N");
  check(!o.angles || (*o.angles >= 1 && *o.angles <= 1000000), "angles is outside [1, 10^6]");
  check(Finite(o.angleStepDegrees), "the angle step is not finite");
  check(!o.photons || (*o.photons > 0.0 && *o.photons <= 1e12), "photons per pixel are outside (0, 1e12]");
  check(o.samples >= 1 && o.samples <= (uint64_t{ 1 } << 40), "sample count is outside [1, 2^40]");
  check(Length(o.sad) && Length(o.sid), "SAD or SID is outside [1e-6, 1e7] mm");
  check(Finite(o.gantryDegrees) && Finite(o.energyKeV) && Finite(o.muWater) && Finite(o.airThreshold),
        "numbers are not finite");
  check(Finite(o.isocenter) && Finite(o.normal) && Finite(o.viewUp) && Finite(o.detectorSize) &&
          Finite(o.detectorSpacing) && Finite(o.detectorOffset) && Finite(o.window),
        "vectors are not finite");
  if (o.detectorSize)
  {
    for (const double s : *o.detectorSize)
    {
      check(s >= 1.0 && s <= 16384.0 && s == std::floor(s), "detector size is not a whole number in [1, 16384]");
    }
  }
  if (o.detectorSpacing)
  {
    for (const double s : *o.detectorSpacing)
    {
      check(Length(s), "detector spacing is outside [1e-6, 1e7] mm");
    }
  }
  check(o.strata == 0 || (o.strata >= 2 && o.strata <= 256), "strata is outside {0} and [2, 256]");
  check(o.raysPerSide >= 1 && o.raysPerSide <= 64, "rays per pixel side is outside [1, 64]");
}
} // namespace

extern "C" int
LLVMFuzzerInitialize(int *, char ***)
{
  itk::Object::GlobalWarningDisplayOff();
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput(const uint8_t * data, size_t size)
{
  const std::vector<std::string> arguments = SplitArguments(data, size);
  try
  {
    CheckAccepted(pbdrr::ParseCommandLine(arguments), arguments);
  }
  catch (const pbdrr::UsageError &)
  {}
  catch (const itk::ExceptionObject &)
  {}
  catch (const std::exception & e)
  {
    Finding(std::string("ParseCommandLine() threw a std::exception that is neither pbdrr::UsageError nor "
                        "itk::ExceptionObject: ") +
              e.what(),
            arguments);
  }
  catch (...)
  {
    Finding("ParseCommandLine() threw something that is not an exception", arguments);
  }
  return 0;
}
