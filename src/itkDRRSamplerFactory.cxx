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
#include "itkDRRSamplerFactory.h"
#include "itkDRRLevelAliasSampler.h"
#include "itkDRRMetropolisSampler.h"
#include "itkDRRPaperHybridSampler.h"
#include "itkDRRStratifiedSampler.h"
#include "itkDRRUniformVolumeSampler.h"

namespace itk
{
namespace
{
template <typename TSampler>
DRRPointSampler::Pointer
Make()
{
  return TSampler::New().GetPointer();
}
} // namespace

const std::vector<DRRSamplerFactory::Entry> &
DRRSamplerFactory::GetEntries()
{
  static const std::vector<Entry> entries = {
    { "level-alias",
      "exact importance sampling by attenuation level (alias table), O(1) per point",
      &Make<DRRLevelAliasSampler> },
    { "paper-hybrid",
      "the paper's Algorithm 1 (uniform level, accept p(l), Russian roulette), exact weights",
      &Make<DRRPaperHybridSampler> },
    { "metropolis",
      "the paper's Markov chain over levels (section 2.2.2), started in its stationary law",
      &Make<DRRMetropolisSampler> },
    { "stratified",
      "systematic sampling of the mass along a Morton curve: even spread, unbiased, beyond the paper",
      &Make<DRRStratifiedSampler> },
    { "mcvr", "Monte Carlo volume rendering baseline: uniform voxels weighted by mu", &Make<DRRUniformVolumeSampler> },
  };
  return entries;
}

DRRPointSampler::Pointer
DRRSamplerFactory::Create(const std::string & name)
{
  for (const Entry & entry : GetEntries())
  {
    if (entry.Name == name)
    {
      return entry.Create();
    }
  }
  itkGenericExceptionMacro("unknown sampler '" << name << "' (known: " << GetNames() << ")");
}

std::string
DRRSamplerFactory::GetNames()
{
  std::string names;
  for (const Entry & entry : GetEntries())
  {
    names += (names.empty() ? "" : ", ") + entry.Name;
  }
  return names;
}
} // namespace itk
