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

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace itk
{
namespace detail
{
namespace
{
/** The float bits of mu > 0: they grow with mu, piecewise linearly in log2 mu, 2^23 per octave. Denormals are
 * scaled into the normal range first (exactly, by 2^64), which keeps the map increasing and continuous. */
inline int64_t
PseudoLog2(float mu)
{
  const bool  denormal = mu < std::numeric_limits<float>::min();
  const float scaled = denormal ? mu * 18446744073709551616.0f : mu;
  uint32_t    bits;
  std::memcpy(&bits, &scaled, sizeof(bits));
  return static_cast<int64_t>(bits) - (denormal ? (int64_t{ 64 } << 23) : 0);
}
} // namespace

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
  m_Mu = nullptr;
  m_Uniform = true;
  m_MaximumCorrection = 1.0;
  m_OwnedVoxels.reset();
  m_Start.clear();
  m_Count.clear();
  m_MeanMu.clear();
  m_MuSum.clear();
  m_TotalMuSum = 0.0;
  if (!volume.HasLevels())
  {
    this->BuildBinned(volume, numberOfBins);
    return;
  }

  // The volume's own levels: one mu each, so every correction is 1 and mu is never read.
  const size_t numberOfLevels = volume.GetNumberOfLevels();
  m_Voxels = volume.GetLevelVoxels();
  m_NumberOfVoxels = volume.GetLevelStart(numberOfLevels);
  for (size_t l = 0; l < numberOfLevels; ++l)
  {
    const uint64_t count = volume.GetLevelStart(l + 1) - volume.GetLevelStart(l);
    const double   mu = volume.GetLevelMu(l);
    m_Start.push_back(volume.GetLevelStart(l));
    m_Count.push_back(static_cast<uint32_t>(count));
    m_MeanMu.push_back(mu);
    // Exact for counts below 2^29, where it equals the sum of the voxels one by one.
    m_MuSum.push_back(static_cast<double>(count) * mu);
    m_TotalMuSum += m_MuSum.back();
  }
}

void
DRRAttenuationLevels::BuildBinned(const DRRAttenuationVolume & volume, unsigned int numberOfBins)
{
  const float *  mu = volume.GetMuBuffer();
  const uint64_t numberOfVoxels = volume.GetNumberOfVoxels();
  m_Mu = mu;
  m_Voxels = nullptr;
  m_NumberOfVoxels = 0;
  if (!(volume.ComputeMaximumMu() > 0.0))
  {
    return;
  }

  // Log-spaced bins between the smallest and largest positive mu: the relative spread of mu inside a bin, and so
  // the spread of the correction weights, is about the same small ratio in every bin. Air takes the extra key
  // numberOfKeys, which keeps the loops below free of branches where air and tissue mix.
  const uint32_t numberOfKeys = std::min(std::max(1u, numberOfBins), 1u << 24);
  const uint32_t airKey = numberOfKeys;
  // key = (PseudoLog2(mu) - PseudoLog2(smallest)) * numberOfKeys / range, in 32.32 fixed point: the scale is
  // rounded down, so the largest mu stays below numberOfKeys. Integer arithmetic, the same bits everywhere.
  const int64_t  logSmallest = PseudoLog2(static_cast<float>(volume.GetSmallestPositiveMu()));
  const uint64_t logRange =
    static_cast<uint64_t>(PseudoLog2(static_cast<float>(volume.ComputeMaximumMu())) - logSmallest) + 1;
  const uint64_t scale = (static_cast<uint64_t>(numberOfKeys) << 32) / logRange;
  const auto     keyOf = [&](float m) {
    const uint64_t offset = static_cast<uint64_t>(std::max<int64_t>(0, PseudoLog2(m) - logSmallest));
    return m > 0.0f ? static_cast<uint32_t>((offset * scale) >> 32) : airKey;
  };

  // Counting sort of the non-air voxels by key over fixed blocks (the volume's, fewer if the per-block tallies
  // would pass 256 MB), merged in block order.
  struct Tally
  {
    std::vector<uint32_t> Count;
    std::vector<double>   MuSum;
    std::vector<float>    SmallestMu;
    std::vector<float>    LargestMu;
  };
  const uint64_t bytesPerKey = sizeof(uint32_t) + sizeof(double) + 2 * sizeof(float);
  const uint64_t numberOfBlocks = std::max<uint64_t>(
    1, std::min<uint64_t>(volume.GetNumberOfBlocks(), (uint64_t{ 1 } << 28) / ((numberOfKeys + 1) * bytesPerKey)));
  const auto         blockBegin = [&](uint64_t b) { return numberOfVoxels * b / numberOfBlocks; };
  std::vector<Tally> tallies(numberOfBlocks);
  DRRAttenuationVolume::ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      Tally & tally = tallies[b];
      tally.Count.assign(numberOfKeys + 1, 0);
      tally.MuSum.assign(numberOfKeys + 1, 0.0);
      tally.SmallestMu.assign(numberOfKeys + 1, std::numeric_limits<float>::max());
      tally.LargestMu.assign(numberOfKeys + 1, 0.0f);
      // Runs of one key (air, and the flat regions of real volumes) are summed in registers, not through memory.
      const uint64_t end = blockBegin(b + 1);
      uint32_t       runKey = keyOf(mu[blockBegin(b)]);
      uint32_t       runCount = 0;
      double         runSum = 0.0;
      float          runSmallest = std::numeric_limits<float>::max();
      float          runLargest = 0.0f;
      const auto     endRun = [&]() {
        tally.Count[runKey] += runCount;
        tally.MuSum[runKey] += runSum;
        tally.SmallestMu[runKey] = std::min(tally.SmallestMu[runKey], runSmallest);
        tally.LargestMu[runKey] = std::max(tally.LargestMu[runKey], runLargest);
      };
      for (uint64_t v = blockBegin(b); v < end; ++v)
      {
        const float    m = mu[v];
        const uint32_t key = keyOf(m);
        if (key != runKey)
        {
          endRun();
          runKey = key;
          runCount = 0;
          runSum = 0.0;
          runSmallest = std::numeric_limits<float>::max();
          runLargest = 0.0f;
        }
        ++runCount;
        runSum += m;
        runSmallest = std::min(runSmallest, m);
        runLargest = std::max(runLargest, m);
      }
      endRun();
    },
    nullptr);

  std::vector<uint64_t> countPerKey(numberOfKeys, 0);
  std::vector<double>   muSumPerKey(numberOfKeys, 0.0);
  std::vector<float>    smallestMuPerKey(numberOfKeys, std::numeric_limits<float>::max());
  std::vector<float>    largestMuPerKey(numberOfKeys, 0.0f);
  for (const Tally & tally : tallies)
  {
    for (uint32_t key = 0; key < numberOfKeys; ++key)
    {
      countPerKey[key] += tally.Count[key];
      muSumPerKey[key] += tally.MuSum[key];
      smallestMuPerKey[key] = std::min(smallestMuPerKey[key], tally.SmallestMu[key]);
      largestMuPerKey[key] = std::max(largestMuPerKey[key], tally.LargestMu[key]);
    }
  }

  // A level per non-empty key; uniform levels (one mu each) need no correction.
  std::vector<uint32_t> levelOfKey(numberOfKeys, std::numeric_limits<uint32_t>::max());
  uint64_t              start = 0;
  double                maximumWeight = 1.0;
  m_Uniform = true;
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
    m_TotalMuSum += muSumPerKey[key];
    m_Uniform = m_Uniform && smallestMuPerKey[key] == largestMuPerKey[key];
    maximumWeight = std::max(maximumWeight, largestMuPerKey[key] / meanMu);
    start += countPerKey[key];
  }
  m_MaximumCorrection = m_Uniform ? 1.0 : maximumWeight;

  // Each block's first slot per key follows the blocks before it; the counts become the fill positions, and the
  // steps say which keys move on: air stays on a scratch slot of its own block, past the lists.
  std::vector<uint32_t> step(numberOfKeys + 1, 1);
  step[airKey] = 0;
  for (uint32_t key = 0; key < numberOfKeys; ++key)
  {
    uint64_t position = countPerKey[key] > 0 ? m_Start[levelOfKey[key]] : 0;
    for (Tally & tally : tallies)
    {
      const uint32_t count = tally.Count[key];
      tally.Count[key] = static_cast<uint32_t>(position);
      position += count;
    }
  }
  for (uint64_t b = 0; b < numberOfBlocks; ++b)
  {
    tallies[b].Count[airKey] = static_cast<uint32_t>(start + b);
  }
  // Written only here, first touched by the threads that fill it: no zero-fill.
  m_OwnedVoxels.reset(new uint32_t[start + numberOfBlocks]);
  m_Voxels = m_OwnedVoxels.get();
  m_NumberOfVoxels = start;
  uint32_t * voxels = m_OwnedVoxels.get();
  DRRAttenuationVolume::ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      uint32_t *     position = tallies[b].Count.data();
      const uint64_t end = blockBegin(b + 1);
      for (uint64_t v = blockBegin(b); v < end; ++v)
      {
        const uint32_t key = keyOf(mu[v]);
        const uint32_t slot = position[key];
        DRRAttenuationVolumeDetail::PrefetchNextLineForWrite(voxels + slot);
        voxels[slot] = static_cast<uint32_t>(v);
        position[key] = slot + step[key];
      }
    },
    nullptr);
}

size_t
DRRAttenuationLevels::GetSizeInBytes() const
{
  return m_NumberOfVoxels * sizeof(uint32_t) +
         m_Count.size() * (sizeof(uint64_t) + sizeof(uint32_t) + 2 * sizeof(double));
}
} // namespace detail
} // namespace itk
