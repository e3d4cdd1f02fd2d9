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
#include "itkDRRCompilerSupport.h"

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
DRRLevelAliasSampler::GenerateBatch(detail::DRRPhiloxRandom & random,
                                    const SampleRange &       range,
                                    uint64_t *                voxelIndex,
                                    double *                  weight) const
{
  this->RequireLevels(range);
  // Blocks of samples in two passes: draw every level and rank, prefetching the list entry, then read the entries.
  // The random reads of a block then overlap instead of waiting one after another (same draws, same results).
  constexpr uint64_t block = 64;
  uint32_t           levels[block];
  uint64_t           ranks[block];
  for (uint64_t first = 0; first < range.Count; first += block)
  {
    const uint64_t count = std::min(block, range.Count - first);
    for (uint64_t i = 0; i < count; ++i)
    {
      const detail::DRRPhiloxRandom::BlockType bits = random.Next();
      levels[i] = m_AliasTable.Draw(bits[0], bits[1]);
      ranks[i] = detail::DRRPhiloxRandom::ToRange(bits[2], bits[3], m_Levels.GetCount(levels[i]));
      PointBasedDRR_PREFETCH(m_Levels.GetVoxelAddress(levels[i], ranks[i]), 0, 3);
    }
    for (uint64_t i = 0; i < count; ++i)
    {
      const uint32_t voxel = m_Levels.GetVoxel(levels[i], ranks[i]);
      voxelIndex[first + i] = voxel;
      weight[first + i] = m_Levels.GetCorrection(voxel, levels[i]);
    }
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
