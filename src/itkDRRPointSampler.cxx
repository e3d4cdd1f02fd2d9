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
#include "itkDRRPointSampler.h"
#include "itkDRRControlVariate.h"

namespace itk
{
void
DRRPointSampler::InitializeWithControlVariate(DRRControlVariate &          controlVariate,
                                              const DRRAttenuationVolume & volume,
                                              unsigned int                 factor,
                                              MultiThreaderBase *          threader)
{
  controlVariate.Build(volume, factor, threader);
  this->Initialize(controlVariate.GetResidualVolume());
}

void
DRRPointSampler::GenerateBatch(detail::DRRPhiloxRandom &, const SampleRange &, uint64_t *, double *) const
{
  itkExceptionMacro("draws voxel coordinates only (GenerateCoordinates()), not linear voxel indices");
}

DRRPointSampler::ViewPlanConstPointer
DRRPointSampler::MakeViewPlan(const DRRAttenuationVolume & volume, const DRRPointProjection *, double, double) const
{
  const auto & size = volume.GetSize();
  return std::make_shared<const DRRSamplerViewPlan>(
    m_TotalMass, DRRSamplerViewPlan::VolumeSizeType{ { size[0], size[1], size[2] } });
}

void
DRRPointSampler::GenerateCoordinates(const DRRSamplerViewPlan & plan,
                                     detail::DRRPhiloxRandom &  random,
                                     const SampleRange &        range,
                                     Cursor &,
                                     const CoordinateBatch & batch) const
{
  this->GenerateBatch(random, range, batch.Voxel, batch.Weight);
  const uint64_t nx = plan.GetVolumeSize()[0];
  const uint64_t nxy = nx * plan.GetVolumeSize()[1];
  for (uint64_t s = 0; s < range.Count; ++s)
  {
    const uint64_t k = batch.Voxel[s] / nxy;
    const uint64_t rest = batch.Voxel[s] - k * nxy;
    const uint64_t j = rest / nx;
    batch.I[s] = static_cast<uint32_t>(rest - j * nx);
    batch.J[s] = static_cast<uint32_t>(j);
    batch.K[s] = static_cast<uint32_t>(k);
  }
}
} // namespace itk
