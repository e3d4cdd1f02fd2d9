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
#include "itkDRRStratifiedSampler.h"
#include "itkDRRCompilerBuiltins.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <array>
#include <limits>

namespace itk
{
namespace
{
constexpr uint64_t brickSide = 8; // voxels per brick side
constexpr uint64_t voxelsPerBrick = brickSide * brickSide * brickSide;

/** Interleaves the bits of x, y, z (x lowest): the Morton code. */
uint64_t
MortonCode(uint64_t x, uint64_t y, uint64_t z)
{
  uint64_t code = 0;
  for (unsigned int bit = 0; bit < 21; ++bit)
  {
    code |= ((x >> bit) & 1u) << (3 * bit) | ((y >> bit) & 1u) << (3 * bit + 1) | ((z >> bit) & 1u) << (3 * bit + 2);
  }
  return code;
}

/** The place of brick (x, y, z) on the sampler's curve: planes of bricks (8 voxels thick) in z, each in 2-D Morton
 * order of (x, y). Any slab of whole brick planes is then one stretch of the curve, so that a render streamed slab by
 * slab (the shared design, section 11) draws the points the whole volume's render draws; inside a plane, neighbours
 * stay together. */
uint64_t
CurveCode(uint64_t x, uint64_t y, uint64_t z)
{
  uint64_t code = 0;
  for (unsigned int bit = 0; bit < 16; ++bit)
  {
    code |= ((x >> bit) & 1u) << (2 * bit) | ((y >> bit) & 1u) << (2 * bit + 1);
  }
  return z << 32 | code;
}

/** Voxel offsets (x | y << 3 | z << 6) of the 512 Morton positions inside a brick. */
struct MortonInsideBrick
{
  MortonInsideBrick()
  {
    for (uint64_t z = 0; z < brickSide; ++z)
    {
      for (uint64_t y = 0; y < brickSide; ++y)
      {
        for (uint64_t x = 0; x < brickSide; ++x)
        {
          const uint64_t code = MortonCode(x, y, z);
          Offset[code] = static_cast<uint16_t>(x | y << 3 | z << 6);
          Code[x | y << 3 | z << 6] = static_cast<uint16_t>(code);
        }
      }
    }
  }
  uint16_t Offset[voxelsPerBrick]; // Morton position -> x | y << 3 | z << 6
  uint16_t Code[voxelsPerBrick];   // x | y << 3 | z << 6 -> Morton position
};

const MortonInsideBrick &
GetMortonInsideBrick()
{
  static const MortonInsideBrick table;
  return table;
}

/** Voxel index (i, j, k) of the voxel at Morton position `position` (0 .. 511) of the brick whose brick coordinates are
 * origin. */
std::array<uint32_t, 3>
VoxelInBrick(const uint16_t origin[3], uint64_t position)
{
  const uint16_t offset = GetMortonInsideBrick().Offset[position];
  return { { static_cast<uint32_t>(origin[0] * brickSide + (offset & 7u)),
             static_cast<uint32_t>(origin[1] * brickSide + ((offset >> 3) & 7u)),
             static_cast<uint32_t>(origin[2] * brickSide + (offset >> 6)) } };
}

/** Lowest set bit. */
unsigned int
LowestBit(uint64_t bits)
{
  return DRRCountTrailingZeros64(bits);
}

/** Reorders items in place so that position p holds what position source[p] held (source: a permutation, consumed),
 * one cycle at a time: one item of scratch instead of a second array. */
template <typename T>
void
GatherInPlace(std::vector<T> & items, std::vector<uint64_t> & source)
{
  for (uint64_t i = 0; i < items.size(); ++i)
  {
    if (source[i] == i)
    {
      continue; // in place, or placed by an earlier cycle
    }
    const T  first = items[i];
    uint64_t j = i;
    while (source[j] != i)
    {
      const uint64_t k = source[j];
      items[j] = items[k];
      source[j] = j;
      j = k;
    }
    items[j] = first;
    source[j] = j;
  }
}

} // namespace

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

/** The bricks a render samples, in curve order, with the mass along the curve before each (1/mm) and after the last;
 * immutable. A slab's plan (MakeSlabViewPlan()) is a stretch of the whole view's curve: its prefix continues the slabs
 * before it, and the walk's step, its choice of search and its end are the whole view's. */
class DRRStratifiedSampler::ViewPlan : public DRRSamplerViewPlan
{
public:
  ViewPlan(double                   sampledMass,
           const VolumeSizeType &   volumeSize,
           std::vector<uint32_t> && bricks,
           std::vector<double> &&   prefix,
           uint64_t                 voxels,
           const SlabPlacement &    placement)
    : DRRSamplerViewPlan(sampledMass, volumeSize)
    , Bricks(std::move(bricks))
    , Prefix(std::move(prefix))
    , Voxels(voxels)
    , WalkMass(placement.ViewMass > 0.0 ? placement.ViewMass : Prefix.back())
    , WalkVoxels(placement.ViewMass > 0.0 ? placement.ViewVoxels : voxels)
    , EndsWalk(placement.LastSlab)
  {}
  const std::vector<uint32_t> Bricks;     // the bricks sampled (all, or those in the view)
  const std::vector<double>   Prefix;     // mass along the curve before each view brick, and after the last (1/mm)
  const uint64_t              Voxels;     // non-air voxels in the plan's bricks
  const double                WalkMass;   // mass of the whole walk (1/mm): its step is WalkMass / (samples per stratum)
  const uint64_t              WalkVoxels; // non-air voxels of the whole walk: sparse or dense search
  const bool                  EndsWalk;   // the plan's last voxel is the walk's (it takes what rounding leaves)
};

const DRRStratifiedSampler::ViewPlan &
DRRStratifiedSampler::AsViewPlan(const DRRSamplerViewPlan & plan)
{
  const auto * own = dynamic_cast<const ViewPlan *>(&plan);
  if (!own)
  {
    itkGenericExceptionMacro("DRRStratifiedSampler: the plan was not made by a DRRStratifiedSampler");
  }
  return *own;
}

void
DRRStratifiedSampler::Initialize(const DRRAttenuationVolume & volume)
{
  const auto & size = volume.GetSize();
  m_Bricks = {}; // the last volume's bricks go before this one's are built
  m_WholeVolumePlan = nullptr;
  m_Volume = &volume;
  m_Size = size;
  m_VoxelVolume = volume.GetVoxelVolume();
  std::array<uint64_t, 3> bricksPerAxis;
  for (unsigned int a = 0; a < 3; ++a)
  {
    bricksPerAxis[a] = (size[a] + brickSide - 1) / brickSide;
    if (bricksPerAxis[a] > std::numeric_limits<uint16_t>::max())
    {
      itkExceptionMacro("volumes of more than " << std::numeric_limits<uint16_t>::max() * brickSide
                                                << " voxels along an axis are not supported (got " << size[a] << ")");
    }
  }
  const MortonInsideBrick & morton = GetMortonInsideBrick();

  // One pass, one row of bricks (fixed y and z) per block, reading whole voxel rows: occupancy and group masses. Group
  // masses are exact sums (see Brick), so the order of this pass does not matter. The sampler keeps no mu: the walk
  // reads a group's voxels from the volume when it reaches it (FillGroupMu()).
  const uint64_t     numberOfBrickRows = bricksPerAxis[1] * bricksPerAxis[2];
  const uint64_t     numberOfGridBricks = bricksPerAxis[0] * numberOfBrickRows;
  std::vector<Brick> grid(numberOfGridBricks); // becomes m_Bricks, reordered in place: the bricks are held once
  DRRAttenuationVolume::ParallelizeBlocks(
    numberOfBrickRows,
    [&](uint64_t brickRow) {
      const uint64_t     by = brickRow % bricksPerAxis[1];
      const uint64_t     bz = brickRow / bricksPerAxis[1];
      Brick *            row = grid.data() + brickRow * bricksPerAxis[0];
      std::vector<float> line(size[0]);
      for (uint64_t bx = 0; bx < bricksPerAxis[0]; ++bx)
      {
        row[bx] = Brick{};
        row[bx].Origin[0] = static_cast<uint16_t>(bx);
        row[bx].Origin[1] = static_cast<uint16_t>(by);
        row[bx].Origin[2] = static_cast<uint16_t>(bz);
      }
      for (uint64_t dz = 0; dz < brickSide && bz * brickSide + dz < size[2]; ++dz)
      {
        for (uint64_t dy = 0; dy < brickSide && by * brickSide + dy < size[1]; ++dy)
        {
          volume.FillMuRow(0, by * brickSide + dy, bz * brickSide + dz, size[0], line.data());
          // Voxels x and x + 4 of a brick's row have the same place in their groups (the Morton code's low 6 bits),
          // in groups g and g + 1. Air adds a zero bit and a zero mass: no branch on noisy data.
          const uint64_t group = ((dy >> 2) & 1u) << 1 | ((dz >> 2) & 1u) << 2;
          uint64_t       place[4];
          for (uint64_t x = 0; x < 4; ++x)
          {
            place[x] = morton.Code[x | dy << 3 | dz << 6] & 63u;
          }
          for (uint64_t bx = 0; bx < bricksPerAxis[0]; ++bx)
          {
            const float *  mu = line.data() + bx * brickSide;
            const uint64_t n = std::min(brickSide, size[0] - bx * brickSide);
            Brick &        brick = row[bx];
            for (uint64_t half = 0; half < 2; ++half)
            {
              uint64_t bits = 0;
              double   mass = brick.GroupMass[group + half];
              for (uint64_t x = 4 * half; x < std::min<uint64_t>(n, 4 * half + 4); ++x)
              {
                bits |= uint64_t{ mu[x] > 0.0f } << place[x & 3u];
                mass += mu[x];
              }
              brick.Occupancy[group + half] |= bits;
              brick.GroupMass[group + half] = mass;
            }
          }
        }
      }
    },
    nullptr);

  // The non-empty bricks in curve order, and the non-air voxels before each: the grid itself, reordered in place and
  // cut after its last non-empty brick (a copy would hold the bricks twice: 1.4 GB on a 4.6 G voxel CT).
  std::vector<std::pair<uint64_t, uint64_t>> coded; // (Morton code, grid index)
  std::vector<uint64_t>                      empty;
  for (uint64_t g = 0; g < numberOfGridBricks; ++g)
  {
    uint64_t occupied = 0;
    for (const uint64_t word : grid[g].Occupancy)
    {
      occupied |= word;
    }
    if (occupied)
    {
      coded.emplace_back(CurveCode(grid[g].Origin[0], grid[g].Origin[1], grid[g].Origin[2]), g);
    }
    else
    {
      empty.push_back(g);
    }
  }
  std::sort(coded.begin(), coded.end());
  const size_t          numberOfBricks = coded.size();
  std::vector<uint64_t> source(numberOfGridBricks); // position b takes grid brick source[b]: non-empty ones first
  for (size_t b = 0; b < numberOfBricks; ++b)
  {
    source[b] = coded[b].second;
  }
  std::copy(empty.begin(), empty.end(), source.begin() + static_cast<std::ptrdiff_t>(numberOfBricks));
  coded = {};
  empty = {};
  GatherInPlace(grid, source);
  source = {};
  grid.resize(numberOfBricks);
  if (grid.capacity() > numberOfBricks + numberOfBricks / 8)
  {
    grid.shrink_to_fit(); // many empty bricks (a CT of mostly air): worth the copy of the rest
  }
  m_Bricks = std::move(grid);
  uint64_t numberOfVoxels = 0;
  double   totalMass = 0.0;
  for (Brick & brick : m_Bricks)
  {
    brick.FirstVoxel = numberOfVoxels;
    brick.Mass = 0.0;
    for (unsigned int g = 0; g < 8; ++g)
    {
      numberOfVoxels += uint64_t{ DRRPopCount64(brick.Occupancy[g]) };
      brick.Mass += brick.GroupMass[g];
      brick.LastGroup = brick.Occupancy[g] ? static_cast<uint8_t>(g) : brick.LastGroup;
    }
    totalMass += brick.Mass;
  }
  m_NumberOfNonAirVoxels = numberOfVoxels;
  m_TotalMass = totalMass * m_VoxelVolume;
  m_MaximumWeight = 1.0;
  m_WholeVolumePlan = this->KeepBricks([](const Brick &) { return true; }, SlabPlacement());
  this->Modified();
}

const float *
DRRStratifiedSampler::CachedGroupMu(uint64_t brick, uint64_t group, Cursor & cursor) const
{
  const uint64_t id = 8 * brick + group;
  if (cursor.CachedGroup != id)
  {
    // The walk goes on along the curve: ask for the next group's voxels (the next brick's first group after the
    // last) while this one is read.
    const uint64_t nextBrick = group < 7 ? brick : brick + 1;
    if (nextBrick < m_Bricks.size())
    {
      this->PrefetchGroup(m_Bricks[nextBrick], group < 7 ? group + 1 : 0);
    }
    this->FillGroupMu(m_Bricks[brick], group, cursor.Cached);
    cursor.CachedGroup = id;
  }
  return cursor.Cached;
}

void
DRRStratifiedSampler::GroupBox(const Brick & brick, uint64_t group, uint64_t first[3], uint64_t count[3]) const
{
  for (unsigned int a = 0; a < 3; ++a)
  {
    first[a] = brick.Origin[a] * brickSide + 4 * ((group >> a) & 1u);
    count[a] = first[a] < m_Size[a] ? std::min<uint64_t>(4, m_Size[a] - first[a]) : 0;
  }
}

void
DRRStratifiedSampler::PrefetchGroup(const Brick & brick, uint64_t group) const
{
  uint64_t first[3], count[3];
  this->GroupBox(brick, group, first, count);
  m_Volume->PrefetchBox(first[0], first[1], first[2], count[0], count[1], count[2]);
}

void
DRRStratifiedSampler::FillGroupMu(const Brick & brick, uint64_t group, float * mu) const
{
  // Group g holds the Morton positions 64 g .. 64 g + 63: the 4 x 4 x 4 voxels at (4 (g & 1), 4 ((g >> 1) & 1),
  // 4 (g >> 2)) in the brick. Read as one box from the volume (clipped to it), then put in Morton order.
  uint64_t first[3], count[3];
  this->GroupBox(brick, group, first, count);
  std::fill(mu, mu + 64, 0.0f);
  if (count[0] == 0 || count[1] == 0 || count[2] == 0)
  {
    return;
  }
  float box[64];
  m_Volume->FillMuBox(first[0], first[1], first[2], count[0], count[1], count[2], box);
  const MortonInsideBrick & morton = GetMortonInsideBrick();
  for (uint64_t z = 0; z < count[2]; ++z)
  {
    for (uint64_t y = 0; y < count[1]; ++y)
    {
      for (uint64_t x = 0; x < count[0]; ++x)
      {
        const uint64_t inBrick =
          (first[0] % brickSide + x) | (first[1] % brickSide + y) << 3 | (first[2] % brickSide + z) << 6;
        mu[morton.Code[inBrick] & 63u] = box[x + count[0] * (y + count[1] * z)];
      }
    }
  }
}

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

size_t
DRRStratifiedSampler::GetTableSizeInBytes() const
{
  const size_t wholeVolumePlan = m_WholeVolumePlan ? m_WholeVolumePlan->Bricks.capacity() * sizeof(uint32_t) +
                                                       m_WholeVolumePlan->Prefix.capacity() * sizeof(double)
                                                   : 0;
  return m_Bricks.size() * sizeof(Brick) + wholeVolumePlan;
}

DRRStratifiedSampler::BrickSummary
DRRStratifiedSampler::GetBrickSummary(size_t b) const
{
  const Brick & brick = m_Bricks.at(b);
  BrickSummary  summary;
  summary.NonAirVoxels = 0;
  for (unsigned int a = 0; a < 3; ++a)
  {
    summary.Origin[a] = uint64_t{ brick.Origin[a] } * brickSide;
  }
  for (const uint64_t word : brick.Occupancy)
  {
    summary.NonAirVoxels += uint64_t{ DRRPopCount64(word) };
  }
  summary.MuSum = brick.Mass;
  return summary;
}

void
DRRStratifiedSampler::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Bricks (non-empty, 8^3 voxels): " << m_Bricks.size() << std::endl;
  os << indent << "Non-air voxels: " << m_NumberOfNonAirVoxels << std::endl;
}
} // namespace itk
