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
#ifndef pbdrrOptionValues_h
#define pbdrrOptionValues_h

// The parsers of pbdrr's option values (pbdrrOptionValues.cxx; OptionDeclarations() calls them): each refuses a bad
// value with a UsageError that names the option and the value.

#include "pbdrrOptions.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pbdrr
{
/** N numbers, each as ParseNumber() reads it. */
template <size_t N>
std::array<double, N>
Numbers(const std::vector<std::string> & values, const std::string & flag)
{
  std::array<double, N> numbers;
  for (size_t i = 0; i < N; ++i)
  {
    numbers[i] = ParseNumber(values[i], flag);
  }
  return numbers;
}

/** Throws the UsageError "FLAG expects one of ALLOWED, got 'VALUE'". */
[[noreturn]] void
ThrowNotOneOf(const std::string & value, const std::string & flag, const std::vector<std::string> & allowed);

/** value, if it is one of allowed. */
std::string
OneOf(const std::string & value, const std::string & flag, const std::vector<std::string> & allowed);

/** The enumerator of the registered policy named value (TEnum: PointBasedDRREnums::ReconstructionKernel and `tent`,
 * ...; the names are PointBasedDRREnums::GetNames<TEnum>()). */
template <typename TEnum>
TEnum
Policy(const std::string & value, const std::string & flag)
{
  TEnum id{};
  if (!itk::PointBasedDRREnums::FromName(value, id))
  {
    ThrowNotOneOf(value, flag, itk::PointBasedDRREnums::GetNames<TEnum>());
  }
  return id;
}

/** --exact NAME: the kernel whose exact projector is called NAME (DRRBoxKernel::ExactReference). */
itk::PointBasedDRREnums::ReconstructionKernel
ExactReferenceKernel(const std::string & value);

/** A length in mm within what a radiograph can mean: 1 nm to 10 km. */
double
PositiveLength(const std::string & value, const std::string & flag, const std::string & name);

/** The registered samplers' names. */
std::vector<std::string>
SamplerNames();

/** A whole number from lowest to highest. */
unsigned
WholeNumber(const std::string & value, const std::string & flag, double lowest, double highest);

/** A size in bytes: a number with an optional unit K, M, G or T (powers of 1024, optionally followed by B or iB), or
 * B; 0 for none. */
uint64_t
ParseByteSize(const std::string & value, const std::string & flag);

/** "1,3,7" (--keep-labels, --drop-labels): labels from 0 to 65535, each once. */
std::vector<uint16_t>
ParseLabelList(const std::string & value, const std::string & flag);

/** --shard K/N: shard K (0 .. N - 1) of N. */
std::array<unsigned, 2>
ParseShard(const std::string & value);

/** --control-variate F|auto|off: the filter's factor (0 off, AutomaticControlVariateFactor for auto). */
unsigned
ControlVariateFactor(const std::string & value);
} // namespace pbdrr

#endif
