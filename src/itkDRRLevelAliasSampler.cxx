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
  const uint64_t numberOfVoxels = volume.GetNumberOfVoxels();
  if (numberOfVoxels > std::numeric_limits<uint32_t>::max())
  {
    itkExceptionMacro("volumes of more than 2^32 - 1 voxels are not supported (got " << numberOfVoxels << ")");
  }
  m_Mu = volume.GetMuBuffer();
  const float * mu = volume.GetMuBuffer();

  if (!volume.GetLevelKeys().empty())
  {
    const std::vector<uint32_t> & keys = volume.GetLevelKeys();
    this->BuildLevels(volume, keys, *std::max_element(keys.begin(), keys.end()) + 1);
  }
  else
  {
    // Log-spaced bins between the smallest and largest positive mu: the relative spread of mu inside a bin, and so
    // the spread of the correction weights, is the same small ratio in every bin.
    float smallest = std::numeric_limits<float>::max();
    float largest = 0.0f;
    for (uint64_t v = 0; v < numberOfVoxels; ++v)
    {
      if (mu[v] > 0.0f)
      {
        smallest = std::min(smallest, mu[v]);
        largest = std::max(largest, mu[v]);
      }
    }
    const uint32_t        numberOfKeys = std::max(1u, m_NumberOfBins);
    std::vector<uint32_t> keys(numberOfVoxels);
    const double          logSmallest = largest > 0.0f ? std::log(static_cast<double>(smallest)) : 0.0;
    const double          logRange = largest > smallest ? std::log(static_cast<double>(largest)) - logSmallest : 1.0;
    for (uint64_t v = 0; v < numberOfVoxels; ++v)
    {
      const double position = mu[v] > 0.0f ? (std::log(static_cast<double>(mu[v])) - logSmallest) / logRange : 0.0;
      keys[v] = std::min(numberOfKeys - 1, static_cast<uint32_t>(std::max(0.0, position * numberOfKeys)));
    }
    this->BuildLevels(volume, keys, numberOfKeys);
  }
}

void
DRRLevelAliasSampler::BuildLevels(const DRRAttenuationVolume &  volume,
                                  const std::vector<uint32_t> & keys,
                                  uint32_t                      numberOfKeys)
{
  const float *  mu = volume.GetMuBuffer();
  const uint64_t numberOfVoxels = volume.GetNumberOfVoxels();

  // Counting sort of the non-air voxels by key.
  std::vector<uint64_t> countPerKey(numberOfKeys, 0);
  std::vector<double>   muSumPerKey(numberOfKeys, 0.0);
  std::vector<float>    firstMuPerKey(numberOfKeys, -1.0f);
  std::vector<float>    largestMuPerKey(numberOfKeys, 0.0f);
  bool                  uniformLevels = true;
  for (uint64_t v = 0; v < numberOfVoxels; ++v)
  {
    if (mu[v] > 0.0f)
    {
      const uint32_t key = keys[v];
      ++countPerKey[key];
      muSumPerKey[key] += mu[v];
      largestMuPerKey[key] = std::max(largestMuPerKey[key], mu[v]);
      if (firstMuPerKey[key] < 0.0f)
      {
        firstMuPerKey[key] = mu[v];
      }
      else if (firstMuPerKey[key] != mu[v])
      {
        uniformLevels = false;
      }
    }
  }
  m_UnitWeights = uniformLevels;

  std::vector<uint32_t> levelOfKey(numberOfKeys, std::numeric_limits<uint32_t>::max());
  m_LevelStart.clear();
  m_LevelCount.clear();
  m_LevelMeanMu.clear();
  std::vector<double> levelMass;
  uint64_t            start = 0;
  double              maximumWeight = 1.0;
  for (uint32_t key = 0; key < numberOfKeys; ++key)
  {
    if (countPerKey[key] == 0)
    {
      continue;
    }
    levelOfKey[key] = static_cast<uint32_t>(m_LevelCount.size());
    const double meanMu = muSumPerKey[key] / static_cast<double>(countPerKey[key]);
    m_LevelStart.push_back(start);
    m_LevelCount.push_back(static_cast<uint32_t>(countPerKey[key]));
    m_LevelMeanMu.push_back(meanMu);
    levelMass.push_back(muSumPerKey[key]);
    maximumWeight = std::max(maximumWeight, largestMuPerKey[key] / meanMu);
    start += countPerKey[key];
  }
  m_MaximumWeight = m_UnitWeights ? 1.0 : maximumWeight;

  m_VoxelIndices.assign(start, 0);
  std::vector<uint64_t> fill(m_LevelStart);
  for (uint64_t v = 0; v < numberOfVoxels; ++v)
  {
    if (mu[v] > 0.0f)
    {
      m_VoxelIndices[fill[levelOfKey[keys[v]]]++] = static_cast<uint32_t>(v);
    }
  }

  double massSum = 0.0;
  for (double m : levelMass)
  {
    massSum += m;
  }
  m_TotalMass = massSum * volume.GetVoxelVolume();
  this->BuildAliasTable(levelMass);
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
DRRLevelAliasSampler::GenerateBatch(DRRPhiloxRandom & random,
                                    uint64_t,
                                    uint64_t count,
                                    uint64_t,
                                    uint64_t * voxelIndex,
                                    double *   weight) const
{
  const uint32_t numberOfLevels = static_cast<uint32_t>(m_LevelCount.size());
  for (uint64_t i = 0; i < count; ++i)
  {
    const DRRPhiloxRandom::BlockType bits = random.Next();
    const uint32_t                   bucket = DRRPhiloxRandom::ToRange32(bits[0], numberOfLevels);
    // A full bucket (threshold 2^32 - 1) also maps its last 2^-32 of probability to itself.
    const uint32_t level = bits[1] < m_AliasThreshold[bucket] ? bucket : m_Alias[bucket];
    const uint64_t voxel =
      m_VoxelIndices[m_LevelStart[level] + DRRPhiloxRandom::ToRange(bits[2], bits[3], m_LevelCount[level])];
    voxelIndex[i] = voxel;
    weight[i] = m_UnitWeights ? 1.0 : static_cast<double>(m_Mu[voxel]) / m_LevelMeanMu[level];
  }
}

size_t
DRRLevelAliasSampler::GetTableSizeInBytes() const
{
  return m_VoxelIndices.size() * sizeof(uint32_t) +
         m_LevelCount.size() * (sizeof(uint64_t) + 3 * sizeof(uint32_t) + sizeof(double));
}

void
DRRLevelAliasSampler::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfBins: " << m_NumberOfBins << std::endl;
  os << indent << "NumberOfLevels: " << m_LevelCount.size() << std::endl;
  os << indent << "UnitWeights: " << m_UnitWeights << std::endl;
  os << indent << "TableSizeInBytes: " << this->GetTableSizeInBytes() << std::endl;
}
} // namespace itk
