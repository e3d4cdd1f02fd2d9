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
#ifndef itkDRRAttenuationVolume_hxx
#define itkDRRAttenuationVolume_hxx

#include "itkDRRAttenuationVolume.h"
#include "itkDRRCompilerSupport.h"
#include "itkDRRTransferFunction.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <limits>
#include <type_traits>

namespace itk
{
namespace DRRAttenuationVolumeDetail
{
/** Largest key of an integer level: 16-bit keys keep the per-block counts small. */
constexpr uint32_t MaximumKey = 65535;

/** Maps input values to integer keys value - offset (offset an integer), for the values that are integers in
 * [offset, offset + MaximumKey]. Integrality is tested on the value itself, before the shift could round a fraction
 * away; float input near zero, the common case, is tested in float arithmetic. */
template <typename TValue>
class IntegerKeyMap
{
public:
  explicit IntegerKeyMap(double offset)
    : m_Offset(offset)
    // Read by the integer and float paths only, whose offsets are small: a volume of huge integral values (3e38 in
    // float) has an offset no int64 holds.
    , m_OffsetInteger(std::abs(offset) <= 4503599627370496.0 ? static_cast<int64_t>(offset) : 0)
    , m_FloatPath(std::abs(offset) <= 16777216.0 - 2.0 * (MaximumKey + 1))
    , m_FloatLowest(static_cast<float>(offset))
    , m_FloatHighest(static_cast<float>(offset + MaximumKey))
  {}

  /** True, with the key, if the value is an integer in range. */
  bool
  operator()(TValue value, uint32_t & key) const
  {
    if constexpr (std::is_integral<TValue>::value && sizeof(TValue) <= 4)
    {
      const int64_t shifted = static_cast<int64_t>(value) - m_OffsetInteger;
      key = static_cast<uint32_t>(shifted);
      return shifted >= 0 && shifted <= MaximumKey;
    }
    else
    {
      if constexpr (std::is_same<TValue, float>::value)
      {
        if (m_FloatPath)
        {
          // Both bounds are exact floats inside the int32 range.
          if (!(value >= m_FloatLowest && value <= m_FloatHighest))
          {
            return false;
          }
          const int32_t integer = static_cast<int32_t>(value);
          key = static_cast<uint32_t>(integer - static_cast<int32_t>(m_OffsetInteger));
          return static_cast<float>(integer) == value;
        }
      }
      const double x = static_cast<double>(value);
      const double shifted = x - m_Offset;
      if (!(shifted >= 0.0 && shifted <= MaximumKey)) // NaN and infinities fail here
      {
        return false;
      }
      // Every double of magnitude >= 2^52 is an integer; below, the conversion to int64 is exact for integers only.
      key = static_cast<uint32_t>(shifted);
      return std::abs(x) >= 4503599627370496.0 || static_cast<double>(static_cast<int64_t>(x)) == x;
    }
  }

private:
  double  m_Offset;
  int64_t m_OffsetInteger;
  bool    m_FloatPath;
  float   m_FloatLowest;
  float   m_FloatHighest;
};

/** Asks for the cache line 64 bytes past an address, ahead of writing it: a hint, which never faults, whatever the
 * address. The counting sorts write thousands of lists at once, an entry at a time; fetching each list's next line
 * while its current one fills keeps the stores from waiting for memory (a third less time on the LIDC chest). */
inline void
PrefetchNextLineForWrite(const void * address)
{
  PointBasedDRR_PREFETCH(reinterpret_cast<const void *>(reinterpret_cast<uintptr_t>(address) + 64), 1, 3);
}

/** True if a value is finite and an integer. */
template <typename TValue>
inline bool
IsInteger(TValue value)
{
  if constexpr (std::is_integral<TValue>::value)
  {
    return true;
  }
  else
  {
    const double x = static_cast<double>(value);
    return std::isfinite(x) && (std::abs(x) >= 4503599627370496.0 || static_cast<double>(static_cast<int64_t>(x)) == x);
  }
}
} // namespace DRRAttenuationVolumeDetail

template <typename TValue>
void
DRRAttenuationVolume::Build(const TValue *              values,
                            const SizeType &            size,
                            const DRRTransferFunction & transfer,
                            MultiThreaderBase *         threader,
                            const LightObject *         valueOwner)
{
  this->Reset(size);
  const uint64_t numberOfVoxels = this->GetNumberOfVoxels();
  if (numberOfVoxels == 0)
  {
    return;
  }
  // First guess: integers in [-32768, 32767], i.e. any int16 CT, counted in the same pass that checks them; uint16
  // input is keyed by its value, so that it can be read in place.
  KeyCounts counts;
  double    offset = std::is_same<TValue, uint16_t>::value ? 0.0 : -32768.0;
  bool      integral = this->CountIntegerKeys(values, offset, counts, threader);
  if (!integral)
  {
    // Else: integers spanning less than 2^16, counted from their smallest value.
    const uint64_t       numberOfBlocks = this->GetNumberOfBlocks();
    std::vector<double>  lowest(numberOfBlocks, std::numeric_limits<double>::infinity());
    std::vector<double>  highest(numberOfBlocks, -std::numeric_limits<double>::infinity());
    std::vector<uint8_t> blockIntegral(numberOfBlocks, 1);
    ParallelizeBlocks(
      numberOfBlocks,
      [&](uint64_t b) {
        const uint64_t end = this->GetBlockBegin(b + 1);
        for (uint64_t v = this->GetBlockBegin(b); v < end; ++v)
        {
          if (!DRRAttenuationVolumeDetail::IsInteger(values[v]))
          {
            blockIntegral[b] = 0;
            return;
          }
          lowest[b] = std::min(lowest[b], static_cast<double>(values[v]));
          highest[b] = std::max(highest[b], static_cast<double>(values[v]));
        }
      },
      threader);
    integral = std::all_of(blockIntegral.begin(), blockIntegral.end(), [](uint8_t i) { return i != 0; });
    if (integral)
    {
      offset = *std::min_element(lowest.begin(), lowest.end());
      integral = *std::max_element(highest.begin(), highest.end()) - offset <= DRRAttenuationVolumeDetail::MaximumKey &&
                 this->CountIntegerKeys(values, offset, counts, threader);
    }
  }
  if (integral)
  {
    this->BuildLevels(values, offset, std::move(counts), transfer);
    this->KeepKeys(values, offset, threader, valueOwner);
    this->Modified();
    return;
  }
  this->BuildMu(values, transfer, threader);
  this->Modified();
}

template <typename TValue>
void
DRRAttenuationVolume::KeepKeys(const TValue *      values,
                               double              offset,
                               MultiThreaderBase * threader,
                               const LightObject * valueOwner)
{
  constexpr bool signed16 = std::is_same<TValue, int16_t>::value;
  constexpr bool unsigned16 = std::is_same<TValue, uint16_t>::value;
  if constexpr (signed16 || unsigned16)
  {
    // 16-bit input keyed from -32768 (int16) or 0 (uint16): the key is the stored word itself, its sign bit flipped
    // for int16; read in place while its owner keeps it.
    if (valueOwner && offset == (signed16 ? -32768.0 : 0.0))
    {
      m_Keys = reinterpret_cast<const uint16_t *>(values);
      m_KeyFlip = signed16 ? 0x8000 : 0;
      m_KeyOwner = valueOwner;
      return;
    }
  }
  // A copy of the keys, 2 bytes per voxel, first touched by the threads that fill it.
  m_OwnKeys.reset(new uint16_t[this->GetNumberOfVoxels()]);
  uint16_t *                                              keys = m_OwnKeys.get();
  const DRRAttenuationVolumeDetail::IntegerKeyMap<TValue> keyOf(offset);
  ParallelizeBlocks(
    this->GetNumberOfBlocks(),
    [&](uint64_t b) {
      const uint64_t end = this->GetBlockBegin(b + 1);
      for (uint64_t v = this->GetBlockBegin(b); v < end; ++v)
      {
        uint32_t key = 0;
        keyOf(values[v], key);
        keys[v] = static_cast<uint16_t>(key);
      }
    },
    threader);
  m_Keys = keys;
  m_KeyFlip = 0;
}

template <typename TValue>
bool
DRRAttenuationVolume::CountIntegerKeys(const TValue *      values,
                                       double              offset,
                                       KeyCounts &         counts,
                                       MultiThreaderBase * threader) const
{
  const uint64_t numberOfBlocks = this->GetNumberOfBlocks();
  counts.Lowest.assign(numberOfBlocks, 0);
  counts.Counts.assign(numberOfBlocks, {});
  if constexpr (std::is_integral<TValue>::value && sizeof(TValue) <= 4)
  {
    return this->CountIntegerKeysInRange(values, static_cast<int64_t>(offset), counts, threader);
  }
  std::atomic<bool>                                       failed{ false };
  const DRRAttenuationVolumeDetail::IntegerKeyMap<TValue> keyOf(offset);
  ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      if (failed.load(std::memory_order_relaxed))
      {
        return;
      }
      // Runs of one value (air) make each increment wait for the last: large blocks count into four histograms in
      // turn, so that four increments are under way at once (a third of the time on the 2x chest), then add them.
      constexpr uint64_t    keys = DRRAttenuationVolumeDetail::MaximumKey + 1;
      const uint64_t        begin = this->GetBlockBegin(b);
      const uint64_t        end = this->GetBlockBegin(b + 1);
      const uint64_t        ways = end - begin >= 16 * keys ? 4 : 1;
      std::vector<uint32_t> histogram(ways * keys, 0);
      bool                  valid = true;
      uint64_t              v = begin;
      for (; ways == 4 && v + 4 <= end; v += 4)
      {
        uint32_t key[4] = {};
        // Not a branch: a failed block is rare, and its counts are dropped.
        for (unsigned int w = 0; w < 4; ++w)
        {
          valid &= keyOf(values[v + w], key[w]);
        }
        for (unsigned int w = 0; w < 4; ++w)
        {
          ++histogram[w * keys + (key[w] & DRRAttenuationVolumeDetail::MaximumKey)];
        }
      }
      for (; v < end; ++v)
      {
        uint32_t key = 0;
        valid &= keyOf(values[v], key);
        ++histogram[key & DRRAttenuationVolumeDetail::MaximumKey];
      }
      if (!valid)
      {
        failed = true;
        return;
      }
      for (uint64_t w = 1; w < ways; ++w)
      {
        std::transform(histogram.begin(),
                       histogram.begin() + keys,
                       histogram.begin() + w * keys,
                       histogram.begin(),
                       std::plus<uint32_t>());
      }
      histogram.resize(keys);
      // Keep the block's own key range only: the volume's range is usually a few thousand keys.
      const auto first = std::find_if(histogram.begin(), histogram.end(), [](uint32_t c) { return c != 0; });
      const auto last = std::find_if(histogram.rbegin(), histogram.rend(), [](uint32_t c) { return c != 0; }).base();
      counts.Lowest[b] = static_cast<uint32_t>(first - histogram.begin());
      counts.Counts[b].assign(first, last);
    },
    threader);
  return !failed;
}

template <typename TValue>
bool
DRRAttenuationVolume::CountIntegerKeysInRange(const TValue *      values,
                                              int64_t             offset,
                                              KeyCounts &         counts,
                                              MultiThreaderBase * threader) const
{
  std::atomic<bool> failed{ false };
  ParallelizeBlocksPerWorker(
    this->GetNumberOfBlocks(),
    [&]() -> BlockFunctionType {
      // The worker's four histograms of the block's range of values, reused from block to block.
      auto histogram = std::make_shared<std::vector<uint32_t>>();
      return [&, histogram](uint64_t b) {
        const TValue * begin = values + this->GetBlockBegin(b);
        const TValue * end = values + this->GetBlockBegin(b + 1);
        if (begin == end)
        {
          counts.Lowest[b] = DRRAttenuationVolumeDetail::MaximumKey + 1; // no key, as the other path counts none
          return;
        }
        if (failed.load(std::memory_order_relaxed))
        {
          return;
        }
        // Every value is an integer: the block's extremes (one pass in vectors, the block then in the cache) say
        // whether all its keys are in range, and bound the histograms to the values present, a few thousand in a CT.
        const uint64_t n = static_cast<uint64_t>(end - begin);
        TValue         smallest = begin[0];
        TValue         largest = begin[0];
        for (uint64_t v = 0; v < n; ++v)
        {
          smallest = begin[v] < smallest ? begin[v] : smallest;
          largest = begin[v] > largest ? begin[v] : largest;
        }
        const int64_t lowest = static_cast<int64_t>(smallest);
        const int64_t span = static_cast<int64_t>(largest) - lowest + 1;
        if (lowest - offset < 0 || lowest - offset + span - 1 > DRRAttenuationVolumeDetail::MaximumKey)
        {
          failed = true;
          return;
        }
        // Runs of one value (air) make each increment wait for the last: the voxels count into four histograms in
        // turn, so that four increments are under way at once, then the four are added.
        histogram->assign(4 * static_cast<uint64_t>(span), 0);
        uint32_t * const way[4] = {
          histogram->data(), histogram->data() + span, histogram->data() + 2 * span, histogram->data() + 3 * span
        };
        uint64_t v = 0;
        for (; v + 4 <= n; v += 4)
        {
          for (unsigned int w = 0; w < 4; ++w)
          {
            ++way[w][static_cast<int64_t>(begin[v + w]) - lowest];
          }
        }
        for (; v < n; ++v)
        {
          ++way[0][static_cast<int64_t>(begin[v]) - lowest];
        }
        std::vector<uint32_t> & blockCounts = counts.Counts[b];
        blockCounts.resize(static_cast<uint64_t>(span));
        for (int64_t key = 0; key < span; ++key)
        {
          blockCounts[key] = way[0][key] + way[1][key] + way[2][key] + way[3][key];
        }
        counts.Lowest[b] = static_cast<uint32_t>(lowest - offset); // both extremes are present: no zero at the ends
      };
    },
    threader);
  return !failed;
}

template <typename TValue>
void
DRRAttenuationVolume::BuildLevels(const TValue *              values,
                                  double                      offset,
                                  KeyCounts &&                counts,
                                  const DRRTransferFunction & transfer)
{
  const uint64_t numberOfBlocks = counts.Lowest.size();
  uint32_t       lowest = DRRAttenuationVolumeDetail::MaximumKey;
  uint32_t       highest = 0;
  for (uint64_t b = 0; b < numberOfBlocks; ++b)
  {
    lowest = std::min(lowest, counts.Lowest[b]);
    highest = std::max(highest, counts.Lowest[b] + static_cast<uint32_t>(counts.Counts[b].size()) - 1);
  }
  const uint32_t        span = highest - lowest + 1;
  std::vector<uint64_t> total(span, 0);
  for (uint64_t b = 0; b < numberOfBlocks; ++b)
  {
    const std::vector<uint32_t> & blockCounts = counts.Counts[b];
    for (size_t k = 0; k < blockCounts.size(); ++k)
    {
      total[counts.Lowest[b] - lowest + k] += blockCounts[k];
    }
  }

  // One transfer-function evaluation per value present; a level per value with mu > 0, in increasing value.
  const DRRAttenuationVolumeDetail::IntegerKeyMap<TValue> keyOf(offset);
  std::vector<uint32_t>                                   levelOfKey(span, std::numeric_limits<uint32_t>::max());
  std::vector<uint8_t>                                    invalid(span, 0);
  bool                                                    anyInvalid = false;
  m_LevelStart.assign(1, 0);
  for (uint32_t k = 0; k < span; ++k)
  {
    if (total[k] == 0)
    {
      continue;
    }
    const double attenuation = transfer.Evaluate(offset + static_cast<double>(lowest + k));
    if (!(attenuation >= 0.0) || !(attenuation <= std::numeric_limits<float>::max()))
    {
      invalid[k] = 1;
      anyInvalid = true;
      continue;
    }
    const float mu = static_cast<float>(attenuation);
    if (mu > 0.0f)
    {
      levelOfKey[k] = static_cast<uint32_t>(m_LevelMu.size());
      m_LevelMu.push_back(mu);
      m_LevelStart.push_back(m_LevelStart.back() + total[k]);
    }
  }
  if (anyInvalid)
  {
    // Error path: the first voxel, in memory order, whose value has no valid attenuation.
    for (uint64_t v = 0;; ++v)
    {
      uint32_t key = 0;
      keyOf(values[v], key);
      if (invalid[key - lowest])
      {
        Failure failure;
        failure.Voxel = v;
        failure.Value = static_cast<double>(values[v]);
        failure.Attenuation = transfer.Evaluate(failure.Value);
        this->Reset(m_Size);
        this->ThrowFailure(failure);
      }
    }
  }

  if (!m_LevelMu.empty())
  {
    // mu need not grow with the input value (piecewise-linear transfer functions).
    m_SmallestPositiveMu = *std::min_element(m_LevelMu.begin(), m_LevelMu.end());
    m_LargestMu = *std::max_element(m_LevelMu.begin(), m_LevelMu.end());
  }

  // The key table, and what the level lists need (MaterializeLevelVoxels()).
  m_KeyMu.assign(DRRAttenuationVolumeDetail::MaximumKey + 1, 0.0f);
  for (uint32_t k = 0; k < span; ++k)
  {
    if (levelOfKey[k] != std::numeric_limits<uint32_t>::max())
    {
      m_KeyMu[lowest + k] = m_LevelMu[levelOfKey[k]];
    }
  }
  m_LevelOfKey = std::move(levelOfKey);
  m_LowestKey = lowest;
  m_KeyCounts = std::move(counts); // kept for the level lists, built on request (MaterializeLevelVoxels())
}

template <typename TValue>
void
DRRAttenuationVolume::BuildMu(const TValue * values, const DRRTransferFunction & transfer, MultiThreaderBase * threader)
{
  const uint64_t       numberOfVoxels = this->GetNumberOfVoxels();
  const uint64_t       numberOfBlocks = this->GetNumberOfBlocks();
  std::vector<Failure> failures(numberOfBlocks);
  std::vector<float>   smallest(numberOfBlocks, std::numeric_limits<float>::max());
  std::vector<float>   largest(numberOfBlocks, 0.0f);
  // Written only here, first touched by the threads that fill it: no zero-fill.
  m_Mu.reset(new float[numberOfVoxels]);
  float * mu = m_Mu.get();
  ParallelizeBlocks(
    numberOfBlocks,
    [&](uint64_t b) {
      Failure &      failure = failures[b];
      const uint64_t end = this->GetBlockBegin(b + 1);
      float          blockSmallest = std::numeric_limits<float>::max();
      float          blockLargest = 0.0f;
      failure.Voxel = numberOfVoxels;
      for (uint64_t v = this->GetBlockBegin(b); v < end; ++v)
      {
        const double value = static_cast<double>(values[v]);
        const double attenuation = std::isfinite(value) ? transfer.Evaluate(value) : 0.0;
        if (!std::isfinite(value) || !(attenuation >= 0.0) || !(attenuation <= std::numeric_limits<float>::max()))
        {
          failure.Voxel = v;
          failure.Value = value;
          failure.Attenuation = attenuation;
          failure.NonFinite = !std::isfinite(value);
          return;
        }
        const float m = static_cast<float>(attenuation);
        mu[v] = m;
        blockSmallest = std::min(blockSmallest, m > 0.0f ? m : std::numeric_limits<float>::max());
        blockLargest = std::max(blockLargest, m);
      }
      smallest[b] = blockSmallest;
      largest[b] = blockLargest;
    },
    threader);
  this->FinishMu(failures, smallest, largest);
}
} // namespace itk

#endif
