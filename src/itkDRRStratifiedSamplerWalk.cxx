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
// DRRStratifiedSampler's plans of a view or a slab, and its walk along the curve (the brick tables:
// itkDRRStratifiedSampler.cxx).
#include "itkDRRStratifiedSampler.h"
#include "itkDRRStratifiedSamplerParts.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <array>
#include <limits>

namespace itk
{
using namespace DRRStratifiedBricks;

std::vector<DRRStratifiedSampler::StratumStart>
DRRStratifiedSampler::StartStrata(const SampleRange & range)
{
  const uint64_t            numberOfStrata = std::max<uint64_t>(range.NumberOfStrata, 1);
  std::vector<StratumStart> strata(numberOfStrata);
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    // Streams of the stratum's own: the same for every chunk on every thread.
    const uint64_t                           id = numberOfStrata > 1 ? r : range.Stratum;
    detail::DRRPhiloxRandom                  offsetStream(range.Seed, id, 2);
    const detail::DRRPhiloxRandom::BlockType u = offsetStream.Next();
    detail::DRRPhiloxRandom                  shiftStream(range.Seed, id, 4);
    const detail::DRRPhiloxRandom::BlockType a = shiftStream.Next();
    strata[r].Offset = static_cast<double>((static_cast<uint64_t>(u[1]) << 21) ^ (u[0] >> 11)) * 0x1.0p-53;
    strata[r].Id = static_cast<uint32_t>(id);
    strata[r].Shift[0] = (uint64_t{ a[0] } << 32) | a[1];
    strata[r].Shift[1] = (uint64_t{ a[2] } << 32) | a[3];
  }
  std::sort(strata.begin(), strata.end(), [](const StratumStart & x, const StratumStart & y) {
    return x.Offset < y.Offset || (x.Offset == y.Offset && x.Id < y.Id);
  });
  return strata;
}

/** How many samples of a run lie below a mass along the curve: the one rule that puts samples in voxels, bricks and
 * slabs alike, so that a walk started anywhere (a chunk, a batch, a slab of a streamed render) gives every sample the
 * voxel the walk from the start gives it. Sample q sits at mass (U_[q % R] + q / R) step (the offsets sorted); the
 * samples below mass x are R floor(y) + #{strata with U < frac(y)}, y = x / step. Offsets are padded with 2 (never
 * below a fraction) to a fixed count, so that the count has no branch. */
class DRRStratifiedSampler::SampleCounter
{
public:
  SampleCounter(const std::vector<StratumStart> & strata, double step)
    : m_NumberOfStrata(strata.size()), m_Few(strata.size() <= paddedStrata), m_InverseStep(1.0 / step), m_Strata(strata)
  {
    for (unsigned int r = 0; r < paddedStrata; ++r)
    {
      m_Offsets[r] = r < m_NumberOfStrata ? strata[r].Offset : 2.0;
    }
  }
  /** Samples below mass (1/mm along the plan's curve). */
  uint64_t
  Below(double mass) const
  {
    const double  y = mass * m_InverseStep;
    const int64_t whole = static_cast<int64_t>(y); // the floor (y >= 0); signed: one instruction
    const double  fraction = y - static_cast<double>(whole);
    uint64_t      below = static_cast<uint64_t>(whole) * m_NumberOfStrata;
    if (m_Few)
    {
      return below + (m_Offsets[0] < fraction ? 1 : 0) + (m_Offsets[1] < fraction ? 1 : 0) +
             (m_Offsets[2] < fraction ? 1 : 0) + (m_Offsets[3] < fraction ? 1 : 0);
    }
    for (const StratumStart & stratum : m_Strata)
    {
      below += stratum.Offset < fraction ? 1 : 0;
    }
    return below;
  }

private:
  static constexpr unsigned int     paddedStrata = 4;
  const uint64_t                    m_NumberOfStrata;
  const bool                        m_Few;
  const double                      m_InverseStep;
  double                            m_Offsets[paddedStrata];
  const std::vector<StratumStart> & m_Strata;
};

template <typename TKeep>
std::shared_ptr<const DRRStratifiedSampler::ViewPlan>
DRRStratifiedSampler::KeepBricks(TKeep && keep, const SlabPlacement & placement) const
{
  std::vector<uint32_t> viewBricks;
  std::vector<double>   viewPrefix;
  uint64_t              viewVoxels = 0;
  double                running = placement.MassBefore;
  for (size_t b = 0; b < m_Bricks.size(); ++b)
  {
    if (keep(m_Bricks[b]))
    {
      viewBricks.push_back(static_cast<uint32_t>(b));
      viewPrefix.push_back(running);
      running += m_Bricks[b].Mass;
      viewVoxels +=
        (b + 1 < m_Bricks.size() ? m_Bricks[b + 1].FirstVoxel : m_NumberOfNonAirVoxels) - m_Bricks[b].FirstVoxel;
    }
  }
  viewPrefix.push_back(running);
  return std::make_shared<const ViewPlan>((running - placement.MassBefore) * m_VoxelVolume,
                                          ViewPlan::VolumeSizeType{ { m_Size[0], m_Size[1], m_Size[2] } },
                                          std::move(viewBricks),
                                          std::move(viewPrefix),
                                          viewVoxels,
                                          placement);
}

DRRPointSampler::ViewPlanConstPointer
DRRStratifiedSampler::MakeViewPlan(const DRRAttenuationVolume &,
                                   const DRRPointProjection * projection,
                                   double                     kernelReach,
                                   double                     pixelReach) const
{
  if (!projection)
  {
    // Every pose: the whole volume (the plan Initialize() made; before it, a plan of no bricks).
    return m_WholeVolumePlan ? m_WholeVolumePlan
                             : this->KeepBricks([](const Brick &) { return true; }, SlabPlacement());
  }
  return this->MakeSlabViewPlan(projection, kernelReach, pixelReach, SlabPlacement());
}

DRRPointSampler::ViewPlanConstPointer
DRRStratifiedSampler::MakeSlabViewPlan(const DRRPointProjection * projection,
                                       double                     kernelReach,
                                       double                     pixelReach,
                                       const SlabPlacement &      placement) const
{
  if (!projection)
  {
    return this->KeepBricks([](const Brick &) { return true; }, placement);
  }
  // A point of brick b lies in [8 b - 0.5 - reach, 8 b + 7.5 + reach] per axis (continuous index of the whole volume:
  // a slab's planes shifted by its first, clipped to what the kernel can reach of the volume) and counts only if it
  // lands within pixelReach of the detector's pixel centres.
  const double margin = 1e-6; // pixels, for rounding
  const double columnLow = -pixelReach - margin;
  const double columnHigh = projection->GetNumberOfColumns() - 1.0 + pixelReach + margin;
  const double rowLow = -pixelReach - margin;
  const double rowHigh = projection->GetNumberOfRows() - 1.0 + pixelReach + margin;
  const double planeShift[3] = { 0.0, 0.0, static_cast<double>(placement.FirstPlane) };
  return this->KeepBricks(
    [&](const Brick & brick) {
      double lower[3], upper[3];
      for (unsigned int a = 0; a < 3; ++a)
      {
        const double first = static_cast<double>(brick.Origin[a]) * brickSide;
        const double last = std::min(first + brickSide, static_cast<double>(m_Size[a])) - 1.0;
        lower[a] = first + planeShift[a] - kernelReach;
        upper[a] = last + planeShift[a] + kernelReach;
      }
      double columnMin = std::numeric_limits<double>::infinity(), columnMax = -columnMin;
      double rowMin = columnMin, rowMax = -columnMin;
      for (unsigned int corner = 0; corner < 8; ++corner)
      {
        const double p[3] = { corner & 1u ? upper[0] : lower[0],
                              corner & 2u ? upper[1] : lower[1],
                              corner & 4u ? upper[2] : lower[2] };
        double column, row, depth;
        projection->ProjectToDetectorPlane(p, column, row, depth);
        if (projection->IsPerspective() && !(depth > 0.0))
        {
          return true; // a brick that reaches the source plane has no bounded image: keep it
        }
        columnMin = std::min(columnMin, column);
        columnMax = std::max(columnMax, column);
        rowMin = std::min(rowMin, row);
        rowMax = std::max(rowMax, row);
      }
      return columnMax >= columnLow && columnMin <= columnHigh && rowMax >= rowLow && rowMin <= rowHigh;
    },
    placement);
}

double
DRRStratifiedSampler::GetMassAtEnd(const DRRSamplerViewPlan & plan)
{
  return AsViewPlan(plan).Prefix.back();
}

uint64_t
DRRStratifiedSampler::GetNumberOfVoxelsInPlan(const DRRSamplerViewPlan & plan)
{
  return AsViewPlan(plan).Voxels;
}

std::array<uint64_t, 2>
DRRStratifiedSampler::GetSampleWindow(const DRRSamplerViewPlan & plan, const SampleRange & run)
{
  const ViewPlan & view = AsViewPlan(plan);
  if (view.Bricks.empty())
  {
    return { { 0, 0 } };
  }
  const std::vector<StratumStart> strata = StartStrata(run);
  const SampleCounter             counter(strata, view.WalkMass / static_cast<double>(run.StratumSize / strata.size()));
  const uint64_t                  first = std::min(counter.Below(view.Prefix.front()), run.StratumSize);
  const uint64_t end = view.EndsWalk ? run.StratumSize : std::min(counter.Below(view.Prefix.back()), run.StratumSize);
  return { { first, std::max(first, end) } };
}

size_t
DRRStratifiedSampler::GetNumberOfBricksInView(const DRRSamplerViewPlan & plan) const
{
  return AsViewPlan(plan).Bricks.size();
}

void
DRRStratifiedSampler::Locate(const ViewPlan &      plan,
                             uint64_t              sample,
                             const SampleCounter & counter,
                             Cursor &              cursor) const
{
  // The voxel whose end holds more than `sample` samples below it, the ends counted as the dense walk counts them
  // (VoxelEnd()), so that both give a sample the same voxel.
  const std::vector<uint32_t> & viewBricks = plan.Bricks;
  const std::vector<double> &   viewPrefix = plan.Prefix;
  const uint64_t                numberOfViewBricks = viewBricks.size();
  uint64_t                      b = cursor.Position[0];
  if (!cursor.Valid || !(counter.Below(viewPrefix[b + 1]) > sample))
  {
    // The first brick whose end holds more samples (the last one if rounding put the sample at the very end).
    const auto first = viewPrefix.begin() + static_cast<std::ptrdiff_t>(cursor.Valid ? b + 1 : 1);
    const auto end =
      std::partition_point(first, viewPrefix.end() - 1, [&](double mass) { return counter.Below(mass) <= sample; });
    b = std::min(static_cast<uint64_t>(end - viewPrefix.begin()) - 1, numberOfViewBricks - 1);
    cursor.Valid = true;
    cursor.Position[0] = b;
    cursor.Position[1] = 0;
    cursor.Position[2] = m_Bricks[viewBricks[b]].Occupancy[0];
    cursor.Position[3] = 0;
    cursor.Mass[0] = 0.0;
    cursor.Mass[1] = 0.0;
  }
  const Brick & brick = m_Bricks[viewBricks[b]];
  const double  base = viewPrefix[b];
  uint64_t      group = cursor.Position[1];
  if (group < brick.LastGroup && counter.Below(base + (cursor.Mass[0] + brick.GroupMass[group])) <= sample)
  {
    // Skip whole groups, then start the walk at the first voxel of the group reached.
    do
    {
      cursor.Mass[0] += brick.GroupMass[group];
      ++group;
    } while (group < brick.LastGroup && counter.Below(base + (cursor.Mass[0] + brick.GroupMass[group])) <= sample);
    cursor.Position[1] = group;
    cursor.Position[2] = brick.Occupancy[group];
    cursor.Mass[1] = cursor.Mass[0];
  }
  // Walk the voxels of the group (never past its last one, which takes what rounding leaves).
  const float * groupMu = this->CachedGroupMu(viewBricks[b], group, cursor);
  uint64_t      bits = cursor.Position[2];
  double        before = cursor.Mass[1];
  for (uint64_t next = bits & (bits - 1);
       next != 0 && counter.Below(base + (before + groupMu[LowestBit(bits)])) <= sample;
       next &= next - 1)
  {
    before += groupMu[LowestBit(bits)];
    bits = next;
  }
  cursor.Position[2] = bits;
  cursor.Mass[1] = before;
}

inline void
DRRStratifiedSampler::CoordinatesAt(const ViewPlan & plan,
                                    const Cursor &   cursor,
                                    uint32_t &       i,
                                    uint32_t &       j,
                                    uint32_t &       k) const
{
  const auto v = VoxelInBrick(m_Bricks[plan.Bricks[cursor.Position[0]]].Origin,
                              64 * cursor.Position[1] + LowestBit(cursor.Position[2]));
  i = v[0];
  j = v[1];
  k = v[2];
}

void
DRRStratifiedSampler::GenerateCoordinates(const DRRSamplerViewPlan & plan,
                                          detail::DRRPhiloxRandom &,
                                          const SampleRange &     range,
                                          Cursor &                cursor,
                                          const CoordinateBatch & batch) const
{
  const ViewPlan &              view = AsViewPlan(plan);
  const std::vector<uint32_t> & viewBricks = view.Bricks;
  const std::vector<double> &   viewPrefix = view.Prefix;
  if (viewBricks.empty())
  {
    return;
  }
  if (cursor.Valid && cursor.Stratum != range.Stratum)
  {
    cursor.Valid = false;
  }
  cursor.Stratum = range.Stratum;
  const std::vector<StratumStart> strata = StartStrata(range);
  const uint64_t                  numberOfStrata = strata.size();
  const SampleCounter counter(strata, view.WalkMass / static_cast<double>(range.StratumSize / numberOfStrata));
  const uint64_t      firstIndex = range.First - range.StratumFirst;
  // Sample q of the run: point q / R of stratum strata[q % R]; kept as (point, position) to avoid divisions.
  uint64_t point = firstIndex / numberOfStrata;
  uint64_t position = firstIndex % numberOfStrata;
  // Jitter: the SplitMix64 finalizer (a bijection of 64-bit words) of a Weyl sequence started at the stratum's uniform
  // shift, so every point's jitter is exactly uniform and neighbours along the curve are decorrelated. (A
  // low-discrepancy R2 sequence here aliased: on the head CT, voxels met at a regular stride of the sequence got nearly
  // equal offsets, a seed-dependent pattern whose amplitude did not fall with N.)
  const auto mix = [](uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  };
  const auto emit = [&](uint64_t s, uint32_t i, uint32_t j, uint32_t k) {
    const StratumStart & stratum = strata[position];
    batch.I[s] = i;
    batch.J[s] = j;
    batch.K[s] = k;
    batch.Weight[s] = 1.0;
    batch.Stratum[s] = stratum.Id;
    const uint64_t first = mix(stratum.Shift[0] + point * 0x9E3779B97F4A7C15ull);
    const uint64_t second = mix(stratum.Shift[1] + point * 0x9E3779B97F4A7C15ull);
    batch.JitterX[s] = static_cast<uint32_t>(first);
    batch.JitterY[s] = static_cast<uint32_t>(first >> 32);
    batch.JitterZ[s] = static_cast<uint32_t>(second);
    if (++position == numberOfStrata)
    {
      position = 0;
      ++point;
    }
  };

  if (range.StratumSize < view.WalkVoxels / 2)
  {
    // Sparse: samples are many voxels apart; find each.
    for (uint64_t s = 0; s < range.Count; ++s)
    {
      this->Locate(view, firstIndex + s, counter, cursor);
      uint32_t i, j, k;
      this->CoordinatesAt(view, cursor, i, j, k);
      emit(s, i, j, k);
    }
    return;
  }
  // Dense: walk the voxels once for all strata and give each voxel the samples whose masses fall in it (only the
  // first sample of a chunk is searched for); then the strata and jitter of the samples.
  if (!cursor.Valid)
  {
    this->Locate(view, firstIndex, counter, cursor);
  }
  const uint64_t endIndex = firstIndex + range.Count;
  uint64_t       index = firstIndex;
  // The cursor (see Locate()) in locals: it changes at every voxel.
  uint64_t b = cursor.Position[0], group = cursor.Position[1], bits = cursor.Position[2];
  double   groupStart = cursor.Mass[0], before = cursor.Mass[1];
  // The group's mu in Morton order, read from the volume when the walk enters the group.
  const float * mu = this->CachedGroupMu(viewBricks[b], group, cursor);
  while (index < endIndex)
  {
    const Brick & brick = m_Bricks[viewBricks[b]];
    const double  base = viewPrefix[b];
    const bool    lastGroupOfWalk = view.EndsWalk && b + 1 == viewBricks.size() && group == brick.LastGroup;
    // The voxels left in the group; the last voxel of the walk takes what rounding leaves. The last voxel of a group
    // ends where the group does (the sum of the group masses, as Locate() skips groups), whatever the rounding of the
    // voxels' sum: every walk, whole or a slab's, then puts the same samples in every group and brick.
    for (; bits; bits &= bits - 1)
    {
      const bool     lastInGroup = !(bits & (bits - 1));
      const double   end = lastInGroup ? groupStart + brick.GroupMass[group] : before + mu[LowestBit(bits)];
      const bool     lastVoxel = lastGroupOfWalk && lastInGroup;
      const uint64_t last = lastVoxel ? endIndex : std::min<uint64_t>(counter.Below(base + end), endIndex);
      if (last > index)
      {
        const auto v = VoxelInBrick(brick.Origin, 64 * group + LowestBit(bits));
        for (uint64_t s = index - firstIndex; s < last - firstIndex; ++s)
        {
          batch.I[s] = v[0];
          batch.J[s] = v[1];
          batch.K[s] = v[2];
        }
        index = last;
        if (index == endIndex)
        {
          break; // the next batch may have more samples in this voxel: stay on it
        }
      }
      before = end;
    }
    if (index == endIndex)
    {
      break;
    }
    // Next group of the brick (its start is the sum of the group masses, as in Locate()), or the next brick.
    if (group < brick.LastGroup)
    {
      do
      {
        groupStart += brick.GroupMass[group];
        ++group;
      } while (!brick.Occupancy[group]);
      before = groupStart;
    }
    else
    {
      ++b;
      group = 0;
      while (!m_Bricks[viewBricks[b]].Occupancy[group])
      {
        ++group;
      }
      groupStart = 0.0;
      before = 0.0;
    }
    bits = m_Bricks[viewBricks[b]].Occupancy[group];
    mu = this->CachedGroupMu(viewBricks[b], group, cursor);
  }
  cursor.Position[0] = b;
  cursor.Position[1] = group;
  cursor.Position[2] = bits;
  cursor.Position[3] = 0;
  cursor.Mass[0] = groupStart;
  cursor.Mass[1] = before;
  for (uint64_t s = 0; s < range.Count; ++s)
  {
    emit(s, batch.I[s], batch.J[s], batch.K[s]);
  }
}
} // namespace itk
