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

/** The paper's Algorithm 1 as published: points counted without the weights that make it unbiased. */
DRRPointSampler::Pointer
MakeUnweightedPaperHybrid()
{
  auto sampler = DRRPaperHybridSampler::New();
  sampler->SetUseExactWeights(false);
  return sampler.GetPointer();
}
} // namespace

const std::vector<DRRSamplerFactory::Entry> &
DRRSamplerFactory::GetEntries()
{
  static const std::vector<Entry> entries = {
    { "level-alias", &Make<DRRLevelAliasSampler> },
    { "paper-hybrid", &Make<DRRPaperHybridSampler>, &MakeUnweightedPaperHybrid },
    { "metropolis", &Make<DRRMetropolisSampler> },
    { "stratified", &Make<DRRStratifiedSampler> },
    { "mcvr", &Make<DRRUniformVolumeSampler> },
  };
  return entries;
}

DRRPointSampler::Pointer
DRRSamplerFactory::Create(const std::string & name, bool paperVariant)
{
  for (const Entry & entry : GetEntries())
  {
    if (entry.Name == name)
    {
      return paperVariant && entry.CreatePaperVariant ? entry.CreatePaperVariant() : entry.Create();
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
