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
#include "itkPointBasedDRREnums.h"
#include "itkDRRPolicies.h"

namespace itk
{
namespace
{
/** The registered policy list of each policy enumeration. */
template <typename TEnum>
struct PolicyListOf;
template <>
struct PolicyListOf<PointBasedDRREnums::Projection>
{
  using Type = DRRPolicies::Beams;
};
template <>
struct PolicyListOf<PointBasedDRREnums::ReconstructionKernel>
{
  using Type = DRRPolicies::Kernels;
};
template <>
struct PolicyListOf<PointBasedDRREnums::Splat>
{
  using Type = DRRPolicies::Splats;
};
} // namespace

template <typename TEnum>
std::vector<std::string>
PointBasedDRREnums::GetNames()
{
  return PolicyListOf<TEnum>::Type::GetNames();
}

template <typename TEnum>
bool
PointBasedDRREnums::FromName(const std::string & name, TEnum & value)
{
  return PolicyListOf<TEnum>::Type::FindByName(name, value);
}

template PointBasedDRR_EXPORT std::vector<std::string>
                              PointBasedDRREnums::GetNames<PointBasedDRREnums::Projection>();
template PointBasedDRR_EXPORT std::vector<std::string>
                              PointBasedDRREnums::GetNames<PointBasedDRREnums::ReconstructionKernel>();
template PointBasedDRR_EXPORT std::vector<std::string>
                              PointBasedDRREnums::GetNames<PointBasedDRREnums::Splat>();
template PointBasedDRR_EXPORT bool
PointBasedDRREnums::FromName(const std::string &, PointBasedDRREnums::Projection &);
template PointBasedDRR_EXPORT bool
PointBasedDRREnums::FromName(const std::string &, PointBasedDRREnums::ReconstructionKernel &);
template PointBasedDRR_EXPORT bool
PointBasedDRREnums::FromName(const std::string &, PointBasedDRREnums::Splat &);

std::string
PointBasedDRREnums::GetName(Projection value)
{
  return DRRPolicies::Beams::GetName(value);
}

std::string
PointBasedDRREnums::GetName(ReconstructionKernel value)
{
  return DRRPolicies::Kernels::GetName(value);
}

std::string
PointBasedDRREnums::GetName(Splat value)
{
  return DRRPolicies::Splats::GetName(value);
}

bool
PointBasedDRREnums::HasSource(Projection value)
{
  return DRRPolicies::Beams::Visit(value, [](auto beam) { return decltype(beam)::HasSource; });
}

std::string
PointBasedDRREnums::GetExactReferenceName(ReconstructionKernel value)
{
  return DRRPolicies::Kernels::Visit(value, [](auto policy) {
    using Kernel = decltype(policy);
    return std::string(Kernel::ExactReference ? Kernel::ExactReference : "");
  });
}

std::ostream &
operator<<(std::ostream & out, const PointBasedDRREnums::Projection value)
{
  return out << DRRPolicies::Beams::GetEnumeratorName(value);
}

std::ostream &
operator<<(std::ostream & out, const PointBasedDRREnums::ReconstructionKernel value)
{
  return out << DRRPolicies::Kernels::GetEnumeratorName(value);
}

std::ostream &
operator<<(std::ostream & out, const PointBasedDRREnums::Splat value)
{
  return out << DRRPolicies::Splats::GetEnumeratorName(value);
}

std::ostream &
operator<<(std::ostream & out, const PointBasedDRREnums::OutputMode value)
{
  switch (value)
  {
    case PointBasedDRREnums::OutputMode::LineIntegral:
      return out << "LineIntegral";
    case PointBasedDRREnums::OutputMode::Transmission:
      return out << "Transmission";
    case PointBasedDRREnums::OutputMode::Gray8:
      return out << "Gray8";
    case PointBasedDRREnums::OutputMode::Gray16:
      return out << "Gray16";
  }
  return out << "INVALID OutputMode";
}

std::ostream &
operator<<(std::ostream & out, const PointBasedDRREnums::TransferFunction value)
{
  switch (value)
  {
    case PointBasedDRREnums::TransferFunction::Natural:
      return out << "Natural";
    case PointBasedDRREnums::TransferFunction::PiecewiseLinear:
      return out << "PiecewiseLinear";
    case PointBasedDRREnums::TransferFunction::Identity:
      return out << "Identity";
    case PointBasedDRREnums::TransferFunction::Materials:
      return out << "Materials";
  }
  return out << "INVALID TransferFunction";
}

std::ostream &
operator<<(std::ostream & out, const PointBasedDRREnums::PointWeighting value)
{
  return out << (value == PointBasedDRREnums::PointWeighting::Unbiased ? "Unbiased" : "PaperCount");
}

std::ostream &
operator<<(std::ostream & out, const PointBasedDRREnums::Similarity value)
{
  return out << (value == PointBasedDRREnums::Similarity::NormalizedCorrelation ? "NormalizedCorrelation"
                                                                                : "GradientCorrelation");
}
} // namespace itk
