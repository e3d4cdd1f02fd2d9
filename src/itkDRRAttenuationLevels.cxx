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
#include "itkDRRAttenuationLevels.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{
void
DRRAttenuationLevels::Build(const DRRAttenuationVolume & volume, unsigned int numberOfBins)
{
  const uint64_t numberOfVoxels = volume.GetNumberOfVoxels();
  if (numberOfVoxels > std::numeric_limits<uint32_t>::max())
  {
    itkGenericExceptionMacro("DRRAttenuationLevels: "
                             << "volumes of more than 2^32 - 1 voxels are not supported (got " << numberOfVoxels
                             << ")");
  }
  m_Mu = volume.GetMuBuffer();
  const float * mu = volume.GetMuBuffer();

  if (!volume.GetLevelKeys().empty())
  {
    const std::vector<uint32_t> & keys = volume.GetLevelKeys();
    this->Group(volume, keys, *std::max_element(keys.begin(), keys.end()) + 1);
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
    const uint32_t        numberOfKeys = std::max(1u, numberOfBins);
    std::vector<uint32_t> keys(numberOfVoxels);
    const double          logSmallest = largest > 0.0f ? std::log(static_cast<double>(smallest)) : 0.0;
    const double          logRange = largest > smallest ? std::log(static_cast<double>(largest)) - logSmallest : 1.0;
    for (uint64_t v = 0; v < numberOfVoxels; ++v)
    {
      const double position = mu[v] > 0.0f ? (std::log(static_cast<double>(mu[v])) - logSmallest) / logRange : 0.0;
      keys[v] = std::min(numberOfKeys - 1, static_cast<uint32_t>(std::max(0.0, position * numberOfKeys)));
    }
    this->Group(volume, keys, numberOfKeys);
  }
}

void
DRRAttenuationLevels::Group(const DRRAttenuationVolume &  volume,
                            const std::vector<uint32_t> & keys,
                            uint32_t                      numberOfKeys)
{
  const float *  mu = volume.GetMuBuffer();
  const uint64_t numberOfVoxels = volume.GetNumberOfVoxels();

  // Counting sort of the non-air voxels by key, in parallel over fixed blocks of consecutive voxels. The blocks
  // depend on the volume alone, never on the threads, and are merged in order: the same levels, in the same voxel
  // order, with the same sums, on any number of threads.
  struct Tally
  {
    std::vector<uint64_t> Count;
    std::vector<double>   MuSum;
    std::vector<float>    FirstMu;
    std::vector<float>    LargestMu;
    bool                  Uniform{ true };
  };
  const uint64_t bytesPerKey = 2 * sizeof(uint64_t) + 2 * sizeof(float);
  const uint64_t numberOfBlocks = std::max<uint64_t>(
    1,
    std::min<uint64_t>({ 64, numberOfVoxels / 65536 + 1, (uint64_t{ 1 } << 28) / (numberOfKeys * bytesPerKey + 1) }));
  const auto         blockBegin = [&](uint64_t b) { return numberOfVoxels * b / numberOfBlocks; };
  std::vector<Tally> tallies(numberOfBlocks);
  auto               threader = MultiThreaderBase::New();
  threader->ParallelizeArray(
    0,
    numberOfBlocks,
    [&](SizeValueType b) {
      Tally & tally = tallies[b];
      tally.Count.assign(numberOfKeys, 0);
      tally.MuSum.assign(numberOfKeys, 0.0);
      tally.FirstMu.assign(numberOfKeys, -1.0f);
      tally.LargestMu.assign(numberOfKeys, 0.0f);
      for (uint64_t v = blockBegin(b); v < blockBegin(b + 1); ++v)
      {
        if (mu[v] > 0.0f)
        {
          const uint32_t key = keys[v];
          ++tally.Count[key];
          tally.MuSum[key] += mu[v];
          tally.LargestMu[key] = std::max(tally.LargestMu[key], mu[v]);
          if (tally.FirstMu[key] < 0.0f)
          {
            tally.FirstMu[key] = mu[v];
          }
          else if (tally.FirstMu[key] != mu[v])
          {
            tally.Uniform = false;
          }
        }
      }
    },
    nullptr);

  std::vector<uint64_t> countPerKey(numberOfKeys, 0);
  std::vector<double>   muSumPerKey(numberOfKeys, 0.0);
  std::vector<float>    firstMuPerKey(numberOfKeys, -1.0f);
  std::vector<float>    largestMuPerKey(numberOfKeys, 0.0f);
  bool                  uniformLevels = true;
  for (const Tally & tally : tallies)
  {
    uniformLevels = uniformLevels && tally.Uniform;
    for (uint32_t key = 0; key < numberOfKeys; ++key)
    {
      if (tally.Count[key] == 0)
      {
        continue;
      }
      countPerKey[key] += tally.Count[key];
      muSumPerKey[key] += tally.MuSum[key];
      largestMuPerKey[key] = std::max(largestMuPerKey[key], tally.LargestMu[key]);
      if (firstMuPerKey[key] < 0.0f)
      {
        firstMuPerKey[key] = tally.FirstMu[key];
      }
      else if (firstMuPerKey[key] != tally.FirstMu[key])
      {
        uniformLevels = false;
      }
    }
  }
  m_Uniform = uniformLevels;

  std::vector<uint32_t> levelOfKey(numberOfKeys, std::numeric_limits<uint32_t>::max());
  m_Start.clear();
  m_Count.clear();
  m_MeanMu.clear();
  m_MuSum.clear();
  uint64_t start = 0;
  double   maximumWeight = 1.0;
  for (uint32_t key = 0; key < numberOfKeys; ++key)
  {
    if (countPerKey[key] == 0)
    {
      continue;
    }
    levelOfKey[key] = static_cast<uint32_t>(m_Count.size());
    const double meanMu = muSumPerKey[key] / static_cast<double>(countPerKey[key]);
    m_Start.push_back(start);
    m_Count.push_back(static_cast<uint32_t>(countPerKey[key]));
    m_MeanMu.push_back(meanMu);
    m_MuSum.push_back(muSumPerKey[key]);
    maximumWeight = std::max(maximumWeight, largestMuPerKey[key] / meanMu);
    start += countPerKey[key];
  }
  m_MaximumCorrection = m_Uniform ? 1.0 : maximumWeight;

  // Each block's first slot per key follows the blocks before it; the counts become the fill positions.
  for (uint32_t key = 0; key < numberOfKeys; ++key)
  {
    if (countPerKey[key] == 0)
    {
      continue;
    }
    uint64_t position = m_Start[levelOfKey[key]];
    for (Tally & tally : tallies)
    {
      const uint64_t count = tally.Count[key];
      tally.Count[key] = position;
      position += count;
    }
  }
  m_VoxelIndices.assign(start, 0);
  threader->ParallelizeArray(
    0,
    numberOfBlocks,
    [&](SizeValueType b) {
      std::vector<uint64_t> & fill = tallies[b].Count;
      for (uint64_t v = blockBegin(b); v < blockBegin(b + 1); ++v)
      {
        if (mu[v] > 0.0f)
        {
          m_VoxelIndices[fill[keys[v]]++] = static_cast<uint32_t>(v);
        }
      }
    },
    nullptr);

  m_TotalMuSum = 0.0;
  for (double m : m_MuSum)
  {
    m_TotalMuSum += m;
  }
}

size_t
DRRAttenuationLevels::GetSizeInBytes() const
{
  return m_VoxelIndices.size() * sizeof(uint32_t) +
         m_Count.size() * (sizeof(uint64_t) + sizeof(uint32_t) + 2 * sizeof(double));
}
} // namespace itk
