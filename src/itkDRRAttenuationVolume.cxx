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
#include "itkDRRAttenuationVolume.h"
#include "itkDRRCompilerSupport.h"
#include "itkPlatformMultiThreader.h"
#include "vnl/vnl_det.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
DRRAttenuationVolume::DRRAttenuationVolume()
{
  m_IndexToPhysical.SetIdentity();
  m_Origin.Fill(0.0);
}

void
DRRAttenuationVolume::Reset(const SizeType & size)
{
  m_Size = size;
  m_Mu.reset();
  m_MuReady.store(false, std::memory_order_release);
  m_LevelMu.clear();
  m_LevelStart.clear();
  m_LevelVoxels.reset();
  m_SmallestPositiveMu = 0.0f;
  m_LargestMu = 0.0f;
  m_VoxelChannels.clear();
  m_NumberOfChannels = 1;
  this->Modified();
}

void
DRRAttenuationVolume::ApplyVoxelMask(const uint8_t * keep, MultiThreaderBase * threader)
{
  float smallest = std::numeric_limits<float>::max();
  float largest = 0.0f;
  if (this->HasLevels())
  {
    // Each level's list, compacted in place: its voxels stay in increasing order; empty levels are dropped.
    uint32_t *            voxels = m_LevelVoxels.get();
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

uint64_t
DRRAttenuationVolume::ComputeNumberOfBlocks(uint64_t numberOfVoxels)
{
  // At least 2^16 voxels per block keep the per-block work (a 2^16-entry histogram) small beside the block's; at
  // most 128 blocks keep the per-block tables small and still balance the load of a few dozen threads.
  return std::max<uint64_t>(1, std::min<uint64_t>(128, numberOfVoxels >> 16));
}

void
DRRAttenuationVolume::ParallelizeBlocks(uint64_t                  numberOfBlocks,
                                        const BlockFunctionType & function,
                                        MultiThreaderBase *       threader)
{
  MultiThreaderBase::Pointer ownThreader;
  if (threader == nullptr)
  {
    // Platform threads of its own: a caller may itself run on a pool thread (a DRR interpolator answering a metric's
    // worker), where waiting for pool tasks queued behind the callers could deadlock.
    ownThreader = PlatformMultiThreader::New();
    threader = ownThreader.GetPointer();
  }
  // One task per worker, blocks handed out one at a time: a worker slowed down by other work takes fewer blocks.
  const uint64_t workers = std::max<uint64_t>(
    1,
    std::min<uint64_t>(numberOfBlocks,
                       std::min(threader->GetNumberOfWorkUnits(), threader->GetMaximumNumberOfThreads())));
  std::atomic<uint64_t> next{ 0 };
  if (workers == 1)
  {
    for (uint64_t b = 0; b < numberOfBlocks; ++b)
    {
      function(b);
    }
    return;
  }
  threader->ParallelizeArray(
    0,
    workers,
    [&](SizeValueType) {
      for (uint64_t b = next++; b < numberOfBlocks; b = next++)
      {
        function(b);
      }
    },
    nullptr);
}

void
DRRAttenuationVolume::ThrowFailure(const Failure & failure) const
{
  std::ostringstream where;
  where << "voxel (" << failure.Voxel % m_Size[0] << ", " << (failure.Voxel / m_Size[0]) % m_Size[1] << ", "
        << failure.Voxel / (m_Size[0] * m_Size[1]) << ")";
  if (failure.NonFinite)
  {
    itkExceptionMacro("the input volume has a non-finite value (" << failure.Value << ") at " << where.str());
  }
  itkExceptionMacro("negative or non-finite attenuation " << failure.Attenuation << " /mm from input value "
                                                          << failure.Value << " at " << where.str()
                                                          << " (is the input in the units the transfer function "
                                                             "expects?)");
}

const float *
DRRAttenuationVolume::MaterializeMu() const
{
  std::lock_guard<std::mutex> lock(m_MuMutex);
  if (m_MuReady.load(std::memory_order_acquire) || !this->HasLevels())
  {
    return m_Mu.get();
  }
  const uint64_t numberOfVoxels = this->GetNumberOfVoxels();
  const size_t   numberOfLevels = m_LevelMu.size();
  float *        mu = new float[numberOfVoxels];
  // Each block first zeroes a run of voxels that fits the cache, then writes the voxels of every level in it,
  // advancing one cursor per level through the level's increasing voxel list.
  constexpr uint64_t run = uint64_t{ 1 } << 18;
  // Platform threads (see ParallelizeBlocks()): the first call may come from inside a pool thread.
  ParallelizeBlocks(
    this->GetNumberOfBlocks(),
    [&](uint64_t b) {
      const uint64_t        begin = this->GetBlockBegin(b);
      const uint64_t        end = this->GetBlockBegin(b + 1);
      const uint32_t *      voxels = m_LevelVoxels.get();
      std::vector<uint64_t> cursor(numberOfLevels);
      for (size_t l = 0; l < numberOfLevels; ++l)
      {
        cursor[l] = static_cast<uint64_t>(
          std::lower_bound(voxels + m_LevelStart[l], voxels + m_LevelStart[l + 1], static_cast<uint32_t>(begin)) -
          voxels);
      }
      for (uint64_t first = begin; first < end; first += run)
      {
        const uint64_t last = std::min(end, first + run);
        std::fill(mu + first, mu + last, 0.0f);
        for (size_t l = 0; l < numberOfLevels; ++l)
        {
          const float    levelMu = m_LevelMu[l];
          const uint64_t levelEnd = m_LevelStart[l + 1];
          uint64_t       c = cursor[l];
          // The next level's list is read where this run left it: ask for that line while this level is written.
          if (l + 1 < numberOfLevels)
          {
            PointBasedDRR_PREFETCH(voxels + cursor[l + 1], 0, 3);
          }
          for (; c < levelEnd && voxels[c] < last; ++c)
          {
            mu[voxels[c]] = levelMu;
          }
          cursor[l] = c;
        }
      }
    },
    nullptr);
  m_Mu.reset(mu);
  m_MuReady.store(true, std::memory_order_release);
  return mu;
}

void
DRRAttenuationVolume::BuildFromMu(const SizeType & size, const MuFunctionType & fill, MultiThreaderBase * threader)
{
  this->Reset(size);
  const uint64_t       numberOfVoxels = this->GetNumberOfVoxels();
  const uint64_t       numberOfBlocks = this->GetNumberOfBlocks();
  std::vector<Failure> failures(numberOfBlocks);
  std::vector<float>   smallest(numberOfBlocks, std::numeric_limits<float>::max());
  std::vector<float>   largest(numberOfBlocks, 0.0f);
  m_Mu.reset(new float[numberOfVoxels]);
  float * mu = m_Mu.get();
  ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      const uint64_t begin = this->GetBlockBegin(b);
      const uint64_t end = this->GetBlockBegin(b + 1);
      fill(begin, end, mu);
      Failure & failure = failures[b];
      failure.Voxel = numberOfVoxels;
      float blockSmallest = std::numeric_limits<float>::max();
      float blockLargest = 0.0f;
      for (uint64_t v = begin; v < end; ++v)
      {
        const float m = mu[v];
        if (!(m >= 0.0f) || !(m <= std::numeric_limits<float>::max()))
        {
          failure.Voxel = v;
          failure.Value = m;
          failure.Attenuation = m;
          return;
        }
        blockSmallest = std::min(blockSmallest, m > 0.0f ? m : std::numeric_limits<float>::max());
        blockLargest = std::max(blockLargest, m);
      }
      smallest[b] = blockSmallest;
      largest[b] = blockLargest;
    },
    threader);
  this->FinishMu(failures, smallest, largest);
  this->Modified();
}

void
DRRAttenuationVolume::FinishMu(const std::vector<Failure> & failures,
                               const std::vector<float> &   smallest,
                               const std::vector<float> &   largest)
{
  for (const Failure & failure : failures)
  {
    if (failure.Voxel < this->GetNumberOfVoxels())
    {
      this->Reset(m_Size);
      this->ThrowFailure(failure);
    }
  }
  if (!largest.empty())
  {
    m_LargestMu = *std::max_element(largest.begin(), largest.end());
    m_SmallestPositiveMu = m_LargestMu > 0.0f ? *std::min_element(smallest.begin(), smallest.end()) : 0.0f;
  }
  m_MuReady.store(true, std::memory_order_release);
}

void
DRRAttenuationVolume::SetIndexToPhysical(const MatrixType & indexToPhysical, const PointType & origin)
{
  m_IndexToPhysical = indexToPhysical;
  m_Origin = origin;
  this->Modified();
}

double
DRRAttenuationVolume::GetVoxelVolume() const
{
  return std::abs(vnl_det(m_IndexToPhysical.GetVnlMatrix()));
}

double
DRRAttenuationVolume::ComputeMuSum() const
{
  double total = 0.0;
  if (this->HasLevels())
  {
    // count * mu: exact in double for counts below 2^29 (mu has 24 bits), where it equals the sum of the level's
    // voxels one by one; correctly rounded above.
    for (size_t l = 0; l < m_LevelMu.size(); ++l)
    {
      total += static_cast<double>(m_LevelStart[l + 1] - m_LevelStart[l]) * static_cast<double>(m_LevelMu[l]);
    }
    return total;
  }
  const float *       mu = this->GetMuBuffer();
  const uint64_t      numberOfBlocks = this->GetNumberOfBlocks();
  std::vector<double> blockSum(numberOfBlocks, 0.0);
  ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      double         sum = 0.0;
      const uint64_t end = this->GetBlockBegin(b + 1);
      for (uint64_t v = this->GetBlockBegin(b); v < end; ++v)
      {
        sum += mu[v];
      }
      blockSum[b] = sum;
    },
    nullptr);
  for (double sum : blockSum)
  {
    total += sum;
  }
  return total;
}

double
DRRAttenuationVolume::ComputeTotalMass() const
{
  return this->ComputeMuSum() * this->GetVoxelVolume();
}

void
DRRAttenuationVolume::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Size: " << m_Size[0] << " x " << m_Size[1] << " x " << m_Size[2] << std::endl;
  os << indent << "IndexToPhysical (mm per index): " << m_IndexToPhysical << std::endl;
  os << indent << "Origin (mm): " << m_Origin << std::endl;
  if (this->HasLevels())
  {
    os << indent << "Levels: " << m_LevelMu.size() << " (" << m_LevelStart.back() << " non-air voxels)" << std::endl;
  }
  else
  {
    os << indent << "Levels: none (mu per voxel)" << std::endl;
  }
  os << indent << "NumberOfChannels: " << m_NumberOfChannels << std::endl;
}
} // namespace itk
