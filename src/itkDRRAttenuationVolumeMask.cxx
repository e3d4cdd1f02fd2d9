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
// DRRAttenuationVolume: the voxels a label selection leaves out, and the channel of every voxel (docs/design.md,
// section 13). The rest of the class is in itkDRRAttenuationVolume.cxx.
#include "itkDRRAttenuationVolume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
void
DRRAttenuationVolume::ApplyVoxelMask(const uint8_t * keep, MultiThreaderBase * threader)
{
  float smallest = std::numeric_limits<float>::max();
  float largest = 0.0f;
  if (this->IsResidual())
  {
    itkExceptionMacro("a residual volume cannot be masked: mask the volume it is the residual of");
  }
  if (this->MaskKeys(keep, threader))
  {
    this->Modified();
    return;
  }
  if (this->HasLevels())
  {
    // Each level's list, compacted in place: its voxels stay in increasing order; empty levels are dropped. The keys
    // no longer tell air from tissue: mu comes from the lists from now on.
    uint32_t * voxels = const_cast<uint32_t *>(this->GetLevelVoxels());
    this->DropKeys();
    std::vector<float>    levelMu;
    std::vector<uint64_t> levelStart{ 0 };
    uint64_t              next = 0;
    for (size_t l = 0; l < m_LevelMu.size(); ++l)
    {
      for (uint64_t e = m_LevelStart[l]; e < m_LevelStart[l + 1]; ++e)
      {
        voxels[next] = voxels[e];
        next += keep[voxels[e]] != 0 ? 1 : 0;
      }
      if (next > levelStart.back())
      {
        levelMu.push_back(m_LevelMu[l]);
        levelStart.push_back(next);
        smallest = std::min(smallest, m_LevelMu[l]);
        largest = std::max(largest, m_LevelMu[l]);
      }
    }
    m_LevelMu = std::move(levelMu);
    m_LevelStart = std::move(levelStart);
    // mu is materialized again from the levels when asked for.
    m_Mu.reset();
    m_MuReady.store(false, std::memory_order_release);
  }
  else
  {
    float *            mu = m_Mu.get();
    const uint64_t     numberOfBlocks = this->GetNumberOfBlocks();
    std::vector<float> blockSmallest(numberOfBlocks, std::numeric_limits<float>::max());
    std::vector<float> blockLargest(numberOfBlocks, 0.0f);
    ParallelizeBlocks(
      numberOfBlocks,
      [&](uint64_t b) {
        const uint64_t end = this->GetBlockBegin(b + 1);
        for (uint64_t v = this->GetBlockBegin(b); v < end; ++v)
        {
          mu[v] = keep[v] != 0 ? mu[v] : 0.0f;
          blockSmallest[b] = std::min(blockSmallest[b], mu[v] > 0.0f ? mu[v] : std::numeric_limits<float>::max());
          blockLargest[b] = std::max(blockLargest[b], mu[v]);
        }
      },
      threader);
    smallest = *std::min_element(blockSmallest.begin(), blockSmallest.end());
    largest = *std::max_element(blockLargest.begin(), blockLargest.end());
  }
  m_SmallestPositiveMu = largest > 0.0f ? smallest : 0.0f;
  m_LargestMu = largest;
  this->Modified();
}

bool
DRRAttenuationVolume::MaskKeys(const uint8_t * keep, MultiThreaderBase * threader)
{
  // An air key of the volume's key range (a level-less key: mu 0, and counted by the level lists' blocks).
  const uint32_t none = std::numeric_limits<uint32_t>::max();
  const auto     air = std::find(m_LevelOfKey.begin(), m_LevelOfKey.end(), none);
  if (!m_Keys || !this->HasLevels() || air == m_LevelOfKey.end())
  {
    return false; // a volume of tissue at every key of its range: the levels are compacted instead
  }
  const uint16_t airKey = static_cast<uint16_t>(m_LowestKey + static_cast<uint32_t>(air - m_LevelOfKey.begin()));
  // The keys copied, the masked voxels set to air: 2 bytes per voxel, where the levels and mu per voxel cost 4 each.
  std::unique_ptr<uint16_t[]> masked(new uint16_t[this->GetNumberOfVoxels()]);
  const uint16_t *            keys = m_Keys;
  const uint16_t              flip = m_KeyFlip;
  ParallelizeBlocks(
    this->GetNumberOfBlocks(),
    [&](uint64_t b) {
      const uint64_t end = this->GetBlockBegin(b + 1);
      for (uint64_t v = this->GetBlockBegin(b); v < end; ++v)
      {
        masked[v] = keep[v] != 0 ? static_cast<uint16_t>(keys[v] ^ flip) : airKey;
      }
    },
    threader);
  KeyCounts counts;
  this->CountIntegerKeys(masked.get(), 0.0, counts, threader);

  // The levels left: those with a voxel kept, in the same order (as the compaction of the level lists gives them).
  std::vector<uint64_t> total(m_LevelOfKey.size(), 0);
  for (size_t b = 0; b < counts.Lowest.size(); ++b)
  {
    for (size_t k = 0; k < counts.Counts[b].size(); ++k)
    {
      total[counts.Lowest[b] - m_LowestKey + k] += counts.Counts[b][k];
    }
  }
  std::vector<float>    levelMu;
  std::vector<uint64_t> levelStart{ 0 };
  for (size_t k = 0; k < m_LevelOfKey.size(); ++k)
  {
    if (m_LevelOfKey[k] == none)
    {
      continue;
    }
    if (total[k] == 0)
    {
      m_LevelOfKey[k] = none;
      m_KeyMu[m_LowestKey + k] = 0.0f;
      continue;
    }
    m_LevelOfKey[k] = static_cast<uint32_t>(levelMu.size());
    levelMu.push_back(m_KeyMu[m_LowestKey + k]);
    levelStart.push_back(levelStart.back() + total[k]);
  }
  m_LevelMu = std::move(levelMu);
  m_LevelStart = std::move(levelStart);
  m_KeyCounts = std::move(counts);
  m_LevelVoxels.reset();
  m_LevelVoxelsReady.store(false, std::memory_order_release);
  m_Mu.reset();
  m_MuReady.store(false, std::memory_order_release);
  m_OwnKeys = std::move(masked);
  m_Keys = m_OwnKeys.get();
  m_KeyFlip = 0;
  m_KeyOwner = nullptr;
  m_LargestMu = m_LevelMu.empty() ? 0.0f : *std::max_element(m_LevelMu.begin(), m_LevelMu.end());
  m_SmallestPositiveMu = m_LevelMu.empty() ? 0.0f : *std::min_element(m_LevelMu.begin(), m_LevelMu.end());
  return true;
}

void
DRRAttenuationVolume::SetVoxelChannels(std::vector<uint8_t> channels, unsigned int numberOfChannels)
{
  if (channels.empty() && numberOfChannels == 1)
  {
    m_VoxelChannels.clear();
    m_NumberOfChannels = 1;
    this->Modified();
    return;
  }
  if (numberOfChannels < 2 || numberOfChannels > 256 || channels.size() != this->GetNumberOfVoxels())
  {
    itkExceptionMacro("voxel channels need one channel per voxel ("
                      << this->GetNumberOfVoxels() << ", not " << channels.size() << ") and 2 to 256 channels, not "
                      << numberOfChannels);
  }
  const auto beyond = std::find_if(channels.begin(), channels.end(), [&](uint8_t c) { return c >= numberOfChannels; });
  if (beyond != channels.end())
  {
    itkExceptionMacro("voxel " << beyond - channels.begin() << " has channel " << int(*beyond) << " of "
                               << numberOfChannels);
  }
  m_VoxelChannels = std::move(channels);
  m_NumberOfChannels = numberOfChannels;
  this->Modified();
}
} // namespace itk
