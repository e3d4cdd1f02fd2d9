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
#include "itkDRRLevelAliasSampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{
void
DRRLevelAliasSampler::Initialize(const DRRAttenuationVolume & volume)
{
  this->InitializeLevels(volume);
  m_AliasTable.Build(m_Levels.GetMuSums());
  this->Modified();
}

void
DRRLevelAliasSampler::GenerateBatch(DRRPhiloxRandom &   random,
                                    const SampleRange & range,
                                    uint64_t *          voxelIndex,
                                    double *            weight) const
{
  const uint64_t count = range.Count;
  for (uint64_t i = 0; i < count; ++i)
  {
    const DRRPhiloxRandom::BlockType bits = random.Next();
    const uint32_t                   level = m_AliasTable.Draw(bits[0], bits[1]);
    const uint32_t                   voxel =
      m_Levels.GetVoxel(level, DRRPhiloxRandom::ToRange(bits[2], bits[3], m_Levels.GetCount(level)));
    voxelIndex[i] = voxel;
    weight[i] = m_Levels.GetCorrection(voxel, level);
  }
}

size_t
DRRLevelAliasSampler::GetTableSizeInBytes() const
{
  return m_Levels.GetSizeInBytes() + m_AliasTable.GetSizeInBytes();
}

void
DRRLevelAliasSampler::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "TableSizeInBytes: " << this->GetTableSizeInBytes() << std::endl;
}
} // namespace itk
