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
#include "itkDRRSubtractCoarseRow.h"
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
  m_LevelVoxelsReady.store(false, std::memory_order_release);
  m_KeyCounts = KeyCounts{};
  m_LevelOfKey.clear();
  m_LowestKey = 0;
  this->DropKeys();
  m_ResidualFine = nullptr;
  m_ResidualCoarse = nullptr;
  m_ResidualFactor = 0;
  m_ResidualShift = 64;
  m_ResidualMuSum = 0.0;
  m_ResidualStatisticsReady.store(false, std::memory_order_release);
  m_SmallestPositiveMu = 0.0f;
  m_LargestMu = 0.0f;
  m_VoxelChannels.clear();
  m_NumberOfChannels = 1;
  m_ChannelLabels.clear();
  this->Modified();
}

void
DRRAttenuationVolume::Initialize()
{
  Superclass::Initialize();
  this->Reset(SizeType{ { 0, 0, 0 } });
  m_BufferedRegion = RegionType(); // the region held goes with the voxels: the next request builds it again
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
  ParallelizeBlocksPerWorker(
    numberOfBlocks, [&function]() -> BlockFunctionType { return std::cref(function); }, threader);
}

void
DRRAttenuationVolume::ParallelizeBlocksPerWorker(uint64_t                                   numberOfBlocks,
                                                 const std::function<BlockFunctionType()> & makeWorker,
                                                 MultiThreaderBase *                        threader)
{
  if (numberOfBlocks == 0)
  {
    return;
  }
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
    const BlockFunctionType function = makeWorker();
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
      const BlockFunctionType function = makeWorker();
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
  if (m_MuReady.load(std::memory_order_acquire))
  {
    return m_Mu.get();
  }
  if (m_Keys || this->IsResidual())
  {
    // Row by row through FillMuRow(), in the fixed blocks (platform threads: see ParallelizeBlocks()).
    auto * mu = new float[this->GetNumberOfVoxels()];
    ParallelizeBlocks(
      this->GetNumberOfBlocks(),
      [&](uint64_t b) {
        this->ForEachMuRun(this->GetBlockBegin(b),
                           this->GetBlockBegin(b + 1),
                           [mu](uint64_t v, const float * m, uint64_t n) { std::copy(m, m + n, mu + v); });
      },
      nullptr);
    m_Mu.reset(mu);
    m_MuReady.store(true, std::memory_order_release);
    return mu;
  }
  if (!this->HasLevels())
  {
    return m_Mu.get();
  }
  const uint64_t numberOfVoxels = this->GetNumberOfVoxels();
  const size_t   numberOfLevels = m_LevelMu.size();
  float *        mu = new float[numberOfVoxels];
  // Each block first zeroes a run of voxels that fits the cache, then writes the voxels of every level in it,
  // advancing one cursor per level through the level's increasing voxel list.
  constexpr uint64_t run = uint64_t{ 1 } << 18;
  const uint32_t *   voxels = this->GetLevelVoxels();
  // Platform threads (see ParallelizeBlocks()): the first call may come from inside a pool thread.
  ParallelizeBlocks(
    this->GetNumberOfBlocks(),
    [&](uint64_t b) {
      const uint64_t        begin = this->GetBlockBegin(b);
      const uint64_t        end = this->GetBlockBegin(b + 1);
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

const uint32_t *
DRRAttenuationVolume::MaterializeLevelVoxels() const
{
  std::lock_guard<std::mutex> lock(m_LevelVoxelsMutex);
  if (m_LevelVoxelsReady.load(std::memory_order_acquire) || !this->HasLevels() || !m_Keys)
  {
    return m_LevelVoxels.get();
  }
  const uint64_t numberOfVoxels = this->GetNumberOfVoxels();
  const uint64_t numberOfBlocks = m_KeyCounts.Lowest.size();
  if (numberOfVoxels > std::numeric_limits<uint32_t>::max() - numberOfBlocks)
  {
    itkExceptionMacro("level lists index their voxels with 32 bits: a volume of "
                      << numberOfVoxels << " voxels has none (use the stratified sampler, which needs no lists)");
  }
  // Counting sort by level over the fixed blocks: each block's voxels of a level follow those of the blocks before
  // it, so every level lists its voxels in increasing order, whatever the threads. Per block and key, where its next
  // voxel goes and whether it moves on (air stays on a slot of its own past the lists, so that the loop below has no
  // branch to mispredict where air and tissue mix).
  const uint32_t                     none = std::numeric_limits<uint32_t>::max();
  const uint64_t                     numberOfListed = m_LevelStart.back();
  std::vector<std::vector<uint32_t>> position(numberOfBlocks);
  std::vector<uint32_t>              step(m_LevelOfKey.size());
  std::vector<uint64_t>              next(m_LevelStart.begin(), m_LevelStart.end() - 1);
  for (size_t k = 0; k < m_LevelOfKey.size(); ++k)
  {
    step[k] = m_LevelOfKey[k] != none ? 1 : 0;
  }
  for (uint64_t b = 0; b < numberOfBlocks; ++b)
  {
    const std::vector<uint32_t> & blockCounts = m_KeyCounts.Counts[b];
    position[b].resize(blockCounts.size());
    for (size_t k = 0; k < blockCounts.size(); ++k)
    {
      const uint32_t level = m_LevelOfKey[m_KeyCounts.Lowest[b] - m_LowestKey + k];
      if (level != none)
      {
        position[b][k] = static_cast<uint32_t>(next[level]);
        next[level] += blockCounts[k];
      }
      else
      {
        position[b][k] = static_cast<uint32_t>(numberOfListed + b);
      }
    }
  }
  // Written only here, first touched by the threads that fill it: no zero-fill. One scratch slot per block for air.
  auto *           voxels = new uint32_t[numberOfListed + numberOfBlocks];
  const uint16_t * keys = m_Keys;
  const uint16_t   flip = m_KeyFlip;
  ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      uint32_t *       blockPosition = position[b].data();
      const uint32_t * blockStep = step.data() + (m_KeyCounts.Lowest[b] - m_LowestKey);
      const uint32_t   blockLowest = m_KeyCounts.Lowest[b];
      const uint64_t   end = this->GetBlockBegin(b + 1);
      for (uint64_t v = this->GetBlockBegin(b); v < end; ++v)
      {
        const uint32_t key = static_cast<uint32_t>(static_cast<uint16_t>(keys[v] ^ flip)) - blockLowest;
        const uint32_t slot = blockPosition[key];
        DRRAttenuationVolumeDetail::PrefetchNextLineForWrite(voxels + slot);
        voxels[slot] = static_cast<uint32_t>(v);
        blockPosition[key] = slot + blockStep[key];
      }
    },
    nullptr);
  m_LevelVoxels.reset(voxels);
  m_LevelVoxelsReady.store(true, std::memory_order_release);
  return voxels;
}

void
DRRAttenuationVolume::DropKeys()
{
  m_Keys = nullptr;
  m_KeyFlip = 0;
  m_OwnKeys.reset();
  m_KeyOwner = nullptr;
  m_KeyMu.clear();
}

template <typename TFunction>
void
DRRAttenuationVolume::ForEachMuRun(uint64_t begin, uint64_t end, TFunction && function) const
{
  std::vector<float> row(std::min<uint64_t>(m_Size[0], end - begin));
  for (uint64_t v = begin; v < end;)
  {
    const uint64_t i = v % m_Size[0];
    const uint64_t line = v / m_Size[0];
    const uint64_t n = std::min(end - v, m_Size[0] - i);
    this->FillMuRow(i, line % m_Size[1], line / m_Size[1], n, row.data());
    function(v, row.data(), n);
    v += n;
  }
}

void
DRRAttenuationVolume::FillMuRowSlow(uint64_t first, uint64_t i, uint64_t j, uint64_t k, uint64_t count, float * out)
  const
{
  if (this->IsResidual())
  {
    // The fine row (air in the padding), then |mu - mu_c| in place, in double as FillResidualRow() computes r.
    const DRRAttenuationVolume & fine = *m_ResidualFine;
    const SizeType &             fineSize = fine.GetSize();
    const SizeType &             coarseSize = m_ResidualCoarse->GetSize();
    const uint64_t               F = m_ResidualFactor;
    const bool                   rowInside = j < fineSize[1] && k < fineSize[2];
    const uint64_t               inside = rowInside && i < fineSize[0] ? std::min(count, fineSize[0] - i) : 0;
    if (inside > 0)
    {
      fine.FillMuRow(i, j, k, inside, out);
    }
    std::fill(out + inside, out + count, 0.0f);
    const uint64_t column = this->CoarseIndex(i);
    detail::SubtractCoarseRow(m_ResidualCoarseMu +
                                coarseSize[0] * (this->CoarseIndex(j) + coarseSize[1] * this->CoarseIndex(k)),
                              F,
                              column,
                              i - column * F,
                              count,
                              out);
    return;
  }
  const float * mu = this->GetMuBuffer() + first;
  std::copy(mu, mu + count, out);
}

void
DRRAttenuationVolume::FillMuBox(uint64_t i, uint64_t j, uint64_t k, uint64_t ni, uint64_t nj, uint64_t nk, float * out)
  const
{
  // Row by row, whatever the volume holds (a residual's rows are computed, air in its padding, FillMuRowSlow()).
  for (uint64_t z = 0; z < nk; ++z)
  {
    for (uint64_t y = 0; y < nj; ++y)
    {
      this->FillMuRow(i, j + y, k + z, ni, out + ni * (y + nj * z));
    }
  }
}

void
DRRAttenuationVolume::PrefetchBox(uint64_t i, uint64_t j, uint64_t k, uint64_t ni, uint64_t nj, uint64_t nk) const
{
  if (ni == 0 || nj == 0 || nk == 0)
  {
    return;
  }
  if (this->IsResidual())
  {
    // The fine voxels inside the fine grid, and the coarse means of the box's rows (one coarse row per F rows).
    const SizeType & fine = m_ResidualFine->GetSize();
    if (i < fine[0] && j < fine[1] && k < fine[2])
    {
      m_ResidualFine->PrefetchBox(
        i, j, k, std::min(ni, fine[0] - i), std::min(nj, fine[1] - j), std::min(nk, fine[2] - k));
    }
    const SizeType & coarse = m_ResidualCoarse->GetSize();
    for (uint64_t z = this->CoarseIndex(k); z <= this->CoarseIndex(k + nk - 1); ++z)
    {
      for (uint64_t y = this->CoarseIndex(j); y <= this->CoarseIndex(j + nj - 1); ++y)
      {
        PointBasedDRR_PREFETCH(m_ResidualCoarseMu + this->CoarseIndex(i) + coarse[0] * (y + coarse[1] * z), 0, 3);
      }
    }
    return;
  }
  const char * base = m_Keys                                      ? reinterpret_cast<const char *>(m_Keys)
                      : m_MuReady.load(std::memory_order_acquire) ? reinterpret_cast<const char *>(m_Mu.get())
                                                                  : nullptr;
  if (!base)
  {
    return;
  }
  const uint64_t bytes = m_Keys ? sizeof(uint16_t) : sizeof(float);
  for (uint64_t z = 0; z < nk; ++z)
  {
    for (uint64_t y = 0; y < nj; ++y)
    {
      // Every cache line of the row: the first, each 64 bytes on, and the last (a short row may end on the next).
      const char * row = base + bytes * (i + m_Size[0] * (j + y + m_Size[1] * (k + z)));
      const char * last = row + bytes * (ni - 1);
      for (const char * line = row; line < last; line += 64)
      {
        PointBasedDRR_PREFETCH(line, 0, 3);
      }
      PointBasedDRR_PREFETCH(last, 0, 3);
    }
  }
}

void
DRRAttenuationVolume::FillResidualRow(uint64_t i, uint64_t j, uint64_t k, uint64_t count, double * out) const
{
  if (!this->IsResidual())
  {
    itkExceptionMacro("FillResidualRow() reads a residual volume (BuildResidual())");
  }
  const DRRAttenuationVolume & fine = *m_ResidualFine;
  const SizeType &             fineSize = fine.GetSize();
  const SizeType &             coarseSize = m_ResidualCoarse->GetSize();
  const uint64_t               F = m_ResidualFactor;
  const float * coarseRow = m_ResidualCoarse->GetMuBuffer() + coarseSize[0] * (j / F + coarseSize[1] * (k / F));
  // The fine row's voxels inside the volume, air beyond it (the padding); in runs of at most 64 on the stack.
  const bool rowInside = j < fineSize[1] && k < fineSize[2];
  float      fineRow[64];
  for (uint64_t x = 0; x < count; x += 64)
  {
    const uint64_t n = std::min<uint64_t>(64, count - x);
    const uint64_t first = i + x;
    const uint64_t inside = rowInside && first < fineSize[0] ? std::min(n, fineSize[0] - first) : 0;
    if (inside > 0)
    {
      fine.FillMuRow(first, j, k, inside, fineRow);
    }
    // The coarse column by a counter, not a division per voxel.
    uint64_t column = first / F;
    uint64_t within = first % F;
    for (uint64_t y = 0; y < n; ++y)
    {
      const double coarse = coarseRow[column];
      const double value = y < inside ? static_cast<double>(fineRow[y]) : 0.0;
      out[x + y] = value - coarse;
      if (++within == F)
      {
        within = 0;
        ++column;
      }
    }
  }
}

void
DRRAttenuationVolume::BuildResidual(const DRRAttenuationVolume & fine,
                                    const DRRAttenuationVolume & coarse,
                                    unsigned int                 factor)
{
  const SizeType & coarseSize = coarse.GetSize();
  this->Reset(SizeType{ { coarseSize[0] * factor, coarseSize[1] * factor, coarseSize[2] * factor } });
  for (unsigned int a = 0; a < 3; ++a)
  {
    if (factor == 0 || coarseSize[a] * factor < fine.GetSize()[a] || (coarseSize[a] - 1) * factor >= fine.GetSize()[a])
    {
      itkExceptionMacro("BuildResidual(): the coarse volume (" << coarseSize[a] << " voxels along axis " << a
                                                               << ") is not the volume (" << fine.GetSize()[a]
                                                               << ") coarsened by " << factor);
    }
  }
  m_ResidualFine = &fine;
  m_ResidualCoarse = &coarse;
  m_ResidualFactor = factor;
  m_ResidualShift = 64;
  for (unsigned int shift = 0; shift < 63; ++shift)
  {
    m_ResidualShift = uint64_t{ factor } == uint64_t{ 1 } << shift ? shift : m_ResidualShift;
  }
  m_ResidualFineReader = fine.GetMuReader();
  m_ResidualCoarseMu = coarse.GetMuBuffer();
  this->SetIndexToPhysical(fine.GetIndexToPhysicalMatrix(), fine.GetOrigin());
  this->Modified();
}

void
DRRAttenuationVolume::ComputeResidualStatistics() const
{
  std::lock_guard<std::mutex> lock(m_MuMutex);
  if (m_ResidualStatisticsReady.load(std::memory_order_acquire))
  {
    return;
  }
  // One pass: the extremes of |r| and its sum in the fixed blocks, each block's in voxel order (as ComputeMuSum() of
  // a volume of mu per voxel). Platform threads: the first request may come from inside a pool thread.
  const uint64_t      numberOfBlocks = this->GetNumberOfBlocks();
  std::vector<double> blockSum(numberOfBlocks, 0.0);
  std::vector<float>  smallest(numberOfBlocks, std::numeric_limits<float>::max());
  std::vector<float>  largest(numberOfBlocks, 0.0f);
  ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      double sum = 0.0;
      float  blockSmallest = std::numeric_limits<float>::max();
      float  blockLargest = 0.0f;
      this->ForEachMuRun(
        this->GetBlockBegin(b), this->GetBlockBegin(b + 1), [&](uint64_t, const float * mu, uint64_t n) {
          for (uint64_t x = 0; x < n; ++x)
          {
            sum += mu[x];
            blockSmallest = std::min(blockSmallest, mu[x] > 0.0f ? mu[x] : std::numeric_limits<float>::max());
            blockLargest = std::max(blockLargest, mu[x]);
          }
        });
      blockSum[b] = sum;
      smallest[b] = blockSmallest;
      largest[b] = blockLargest;
    },
    nullptr);
  m_ResidualMuSum = 0.0;
  for (const double sum : blockSum)
  {
    m_ResidualMuSum += sum;
  }
  m_LargestMu = *std::max_element(largest.begin(), largest.end());
  m_SmallestPositiveMu = m_LargestMu > 0.0f ? *std::min_element(smallest.begin(), smallest.end()) : 0.0f;
  m_ResidualStatisticsReady.store(true, std::memory_order_release);
}

double
DRRAttenuationVolume::GetBytesPerVoxel() const
{
  const double voxels = static_cast<double>(std::max<uint64_t>(1, this->GetNumberOfVoxels()));
  double       bytes = 0.0;
  bytes += m_OwnKeys ? 2.0 * voxels : 0.0;
  bytes += m_KeyMu.size() * sizeof(float);
  bytes += m_MuReady.load(std::memory_order_acquire) && m_Mu ? 4.0 * voxels : 0.0;
  bytes += m_LevelVoxelsReady.load(std::memory_order_acquire) && m_LevelVoxels
             ? 4.0 * static_cast<double>(m_LevelStart.empty() ? 0 : m_LevelStart.back())
             : 0.0;
  bytes += static_cast<double>(m_VoxelChannels.size());
  return bytes / voxels;
}

void
DRRAttenuationVolume::BuildFromMu(const SizeType & size, const MuFunctionType & fill, MultiThreaderBase * threader)
{
  this->Reset(size);
  m_Mu.reset(new float[this->GetNumberOfVoxels()]);
  this->FinishMuBuffer(&fill, threader);
}

void
DRRAttenuationVolume::BuildFromMu(const SizeType & size, std::unique_ptr<float[]> mu, MultiThreaderBase * threader)
{
  this->Reset(size);
  m_Mu = std::move(mu);
  this->FinishMuBuffer(nullptr, threader);
}

void
DRRAttenuationVolume::FinishMuBuffer(const MuFunctionType * fill, MultiThreaderBase * threader)
{
  const uint64_t       numberOfVoxels = this->GetNumberOfVoxels();
  const uint64_t       numberOfBlocks = this->GetNumberOfBlocks();
  std::vector<Failure> failures(numberOfBlocks);
  std::vector<float>   smallest(numberOfBlocks, std::numeric_limits<float>::max());
  std::vector<float>   largest(numberOfBlocks, 0.0f);
  float *              mu = m_Mu.get();
  ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      const uint64_t begin = this->GetBlockBegin(b);
      const uint64_t end = this->GetBlockBegin(b + 1);
      if (fill)
      {
        (*fill)(begin, end, mu);
      }
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
  if (this->IsResidual())
  {
    this->EnsureResidualStatistics();
    return m_ResidualMuSum;
  }
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
  os << indent << "BufferedRegion: " << m_BufferedRegion.GetIndex() << " + " << m_BufferedRegion.GetSize() << std::endl;
  if (this->IsResidual())
  {
    os << indent << "Residual of a control variate, factor " << m_ResidualFactor << std::endl;
  }
  else if (this->HasLevels())
  {
    os << indent << "Levels: " << m_LevelMu.size() << " (" << m_LevelStart.back() << " non-air voxels)"
       << (m_Keys ? (m_OwnKeys ? ", keys copied" : ", keys read in place") : "") << std::endl;
  }
  else
  {
    os << indent << "Levels: none (mu per voxel)" << std::endl;
  }
  os << indent << "NumberOfChannels: " << m_NumberOfChannels << std::endl;
  os << indent << "BytesPerVoxel (beyond the input): " << this->GetBytesPerVoxel() << std::endl;
}
} // namespace itk
