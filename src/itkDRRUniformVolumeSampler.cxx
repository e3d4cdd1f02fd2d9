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
#include "itkDRRUniformVolumeSampler.h"

namespace itk
{
void
DRRUniformVolumeSampler::Initialize(const DRRAttenuationVolume & volume)
{
  // mu is read at every sample (a volume of levels materializes it here); the sum and the maximum come from the
  // levels when there are levels, else from fixed blocks of voxels summed in order.
  m_Mu = volume.GetMuBuffer();
  m_NumberOfVoxels = volume.GetNumberOfVoxels();
  const double muSum = volume.ComputeMuSum();
  m_TotalMass = muSum * volume.GetVoxelVolume();
  m_WeightPerMu = muSum > 0.0 ? static_cast<double>(m_NumberOfVoxels) / muSum : 0.0;
  m_MaximumWeight = std::max(1.0, volume.ComputeMaximumMu() * m_WeightPerMu);
  this->Modified();
}

void
DRRUniformVolumeSampler::GenerateBatch(detail::DRRPhiloxRandom & random,
                                       const SampleRange &       range,
                                       uint64_t *                voxelIndex,
                                       double *                  weight) const
{
  const uint64_t count = range.Count;
  for (uint64_t i = 0; i < count; ++i)
  {
    const detail::DRRPhiloxRandom::BlockType bits = random.Next();
    const uint64_t voxel = detail::DRRPhiloxRandom::ToRange(bits[0], bits[1], m_NumberOfVoxels);
    voxelIndex[i] = voxel;
    weight[i] = static_cast<double>(m_Mu[voxel]) * m_WeightPerMu;
  }
}
} // namespace itk
