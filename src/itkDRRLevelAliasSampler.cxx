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
  m_Levels.Build(volume, m_NumberOfBins);
  std::vector<double> levelMass(m_Levels.GetNumberOfLevels());
  for (size_t l = 0; l < levelMass.size(); ++l)
  {
    levelMass[l] = m_Levels.GetMuSum(l);
  }
  this->BuildAliasTable(levelMass);
  m_TotalMass = m_Levels.GetTotalMuSum() * volume.GetVoxelVolume();
  m_MaximumWeight = m_Levels.GetMaximumCorrection();
  this->Modified();
}

void
DRRLevelAliasSampler::BuildAliasTable(const std::vector<double> & levelMass)
{
  // Vose's alias method. Bucket b keeps itself with probability threshold[b] / 2^32, else goes to alias[b].
  const size_t numberOfLevels = levelMass.size();
  m_AliasThreshold.assign(numberOfLevels, std::numeric_limits<uint32_t>::max());
  m_Alias.resize(numberOfLevels);
  if (numberOfLevels == 0)
  {
    return;
  }
  double total = 0.0;
  for (double m : levelMass)
  {
    total += m;
  }
  std::vector<double> scaled(numberOfLevels);
  std::vector<size_t> small;
  std::vector<size_t> large;
  for (size_t l = 0; l < numberOfLevels; ++l)
  {
    scaled[l] = levelMass[l] / total * static_cast<double>(numberOfLevels);
    m_Alias[l] = static_cast<uint32_t>(l);
    (scaled[l] < 1.0 ? small : large).push_back(l);
  }
  while (!small.empty() && !large.empty())
  {
    const size_t s = small.back();
    small.pop_back();
    const size_t g = large.back();
    m_AliasThreshold[s] = static_cast<uint32_t>(std::min(4294967295.0, std::floor(scaled[s] * 4294967296.0 + 0.5)));
    m_Alias[s] = static_cast<uint32_t>(g);
    scaled[g] = (scaled[g] + scaled[s]) - 1.0;
    if (scaled[g] < 1.0)
    {
      large.pop_back();
      small.push_back(g);
    }
  }
  // Whatever is left has probability 1 up to rounding: keep itself always.
  for (size_t l : small)
  {
    m_AliasThreshold[l] = std::numeric_limits<uint32_t>::max();
    m_Alias[l] = static_cast<uint32_t>(l);
  }
  for (size_t l : large)
  {
    m_AliasThreshold[l] = std::numeric_limits<uint32_t>::max();
    m_Alias[l] = static_cast<uint32_t>(l);
  }
}

void
DRRLevelAliasSampler::GenerateBatch(DRRPhiloxRandom &   random,
                                    const SampleRange & range,
                                    uint64_t *          voxelIndex,
                                    double *            weight) const
{
  const uint64_t count = range.Count;
  const uint32_t numberOfLevels = static_cast<uint32_t>(m_Levels.GetNumberOfLevels());
  for (uint64_t i = 0; i < count; ++i)
  {
    const DRRPhiloxRandom::BlockType bits = random.Next();
    const uint32_t                   bucket = DRRPhiloxRandom::ToRange32(bits[0], numberOfLevels);
    // A full bucket (threshold 2^32 - 1) also maps its last 2^-32 of probability to itself.
    const uint32_t level = bits[1] < m_AliasThreshold[bucket] ? bucket : m_Alias[bucket];
    const uint32_t voxel =
      m_Levels.GetVoxel(level, DRRPhiloxRandom::ToRange(bits[2], bits[3], m_Levels.GetCount(level)));
    voxelIndex[i] = voxel;
    weight[i] = m_Levels.GetCorrection(voxel, level);
  }
}

size_t
DRRLevelAliasSampler::GetTableSizeInBytes() const
{
  return m_Levels.GetSizeInBytes() + m_Alias.size() * 2 * sizeof(uint32_t);
}

void
DRRLevelAliasSampler::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfBins: " << m_NumberOfBins << std::endl;
  os << indent << "NumberOfLevels: " << m_Levels.GetNumberOfLevels() << std::endl;
  os << indent << "TableSizeInBytes: " << this->GetTableSizeInBytes() << std::endl;
}
} // namespace itk
