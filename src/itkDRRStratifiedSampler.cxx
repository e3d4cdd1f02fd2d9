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
#include "itkDRRControlVariate.h"
#include "itkDRRStratifiedSamplerParts.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <array>
#include <limits>

namespace itk
{
using namespace DRRStratifiedBricks;

namespace
{
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

/** The rank of every brick of a plane of bricks (x fastest) on the curve inside its plane: the 2-D Morton order of
 * (x, y), the same in every plane. Sorted once per plane shape, not once per brick of the volume. */
std::vector<uint32_t>
RankInPlane(uint64_t columns, uint64_t rows)
{
  std::vector<std::pair<uint64_t, uint32_t>> coded(columns * rows); // (curve code, brick of the plane)
  for (uint64_t y = 0; y < rows; ++y)
  {
    for (uint64_t x = 0; x < columns; ++x)
    {
      coded[x + columns * y] = { CurveCode(x, y, 0), static_cast<uint32_t>(x + columns * y) };
    }
  }
  std::sort(coded.begin(), coded.end());
  std::vector<uint32_t> rank(coded.size());
  for (size_t r = 0; r < coded.size(); ++r)
  {
    rank[coded[r].second] = static_cast<uint32_t>(r);
  }
  return rank;
}

/** The occupancy bits of four voxels of a brick's row for each of the 16 patterns of which of them are not air (bit x:
 * voxel x): bit place[x] for voxel x. */
std::array<uint64_t, 16>
OccupancyOfPatterns(const uint64_t place[4])
{
  std::array<uint64_t, 16> bits{};
  for (uint64_t pattern = 0; pattern < 16; ++pattern)
  {
    for (uint64_t x = 0; x < 4; ++x)
    {
      bits[pattern] |= ((pattern >> x) & 1u) << place[x];
    }
  }
  return bits;
}

/** Fills the bricks of the row (by, bz) of a grid of the given size: brick bx at plane[rankInPlane[bx]], its place on
 * the curve inside its plane of bricks; FirstVoxel holds the brick's own count of non-air voxels. rowOf(y, z) gives mu
 * (1/mm) of the whole row (y, z), valid until its next call. (A template: the brick is the sampler's private type.) */
template <typename TBrick, typename TRowOf>
void
BuildBrickRow(const DRRAttenuationVolume::SizeType & size,
              uint64_t                               by,
              uint64_t                               bz,
              const uint32_t *                       rankInPlane,
              TBrick *                               plane,
              TRowOf &&                              rowOf)
{
  const uint64_t            bricks = (size[0] + brickSide - 1) / brickSide;
  const uint64_t            wholeBricks = size[0] / brickSide;
  const MortonInsideBrick & morton = GetMortonInsideBrick();
  for (uint64_t bx = 0; bx < bricks; ++bx)
  {
    TBrick & brick = plane[rankInPlane[bx]];
    std::fill(std::begin(brick.Occupancy), std::end(brick.Occupancy), uint64_t{ 0 });
    std::fill(std::begin(brick.GroupMass), std::end(brick.GroupMass), 0.0);
    brick.Mass = 0.0;
    brick.FirstVoxel = 0;
    brick.LastGroup = 0;
    brick.Origin[0] = static_cast<uint16_t>(bx);
    brick.Origin[1] = static_cast<uint16_t>(by);
    brick.Origin[2] = static_cast<uint16_t>(bz);
  }
  for (uint64_t dz = 0; dz < brickSide && bz * brickSide + dz < size[2]; ++dz)
  {
    for (uint64_t dy = 0; dy < brickSide && by * brickSide + dy < size[1]; ++dy)
    {
      const float * line = rowOf(by * brickSide + dy, bz * brickSide + dz);
      // Voxels x and x + 4 of a brick's row have the same place in their groups (the Morton code's low 6 bits), in
      // groups g and g + 1. Air adds a zero bit and a zero mass: no branch on noisy data. Group masses are exact sums
      // (see Brick), so the order of this pass does not matter.
      const uint64_t group = ((dy >> 2) & 1u) << 1 | ((dz >> 2) & 1u) << 2;
      uint64_t       place[4];
      for (uint64_t x = 0; x < 4; ++x)
      {
        place[x] = morton.Code[x | dy << 3 | dz << 6] & 63u;
      }
      // Whole bricks: four compares make a pattern, one lookup its bits (no shift per voxel).
      const std::array<uint64_t, 16> occupancy = OccupancyOfPatterns(place);
      for (uint64_t bx = 0; bx < wholeBricks; ++bx)
      {
        const float * mu = line + bx * brickSide;
        TBrick &      brick = plane[rankInPlane[bx]];
        for (uint64_t half = 0; half < 2; ++half)
        {
          const float * four = mu + 4 * half;
          brick.Occupancy[group + half] |= occupancy[DRRPositiveMask4(four)];
          double mass = brick.GroupMass[group + half];
          mass += four[0];
          mass += four[1];
          mass += four[2];
          mass += four[3];
          brick.GroupMass[group + half] = mass;
        }
      }
      for (uint64_t bx = wholeBricks; bx < bricks; ++bx)
      {
        const float *  mu = line + bx * brickSide;
        const uint64_t n = size[0] - bx * brickSide;
        TBrick &       brick = plane[rankInPlane[bx]];
        for (uint64_t x = 0; x < n; ++x)
        {
          brick.Occupancy[group + x / 4] |= uint64_t{ mu[x] > 0.0f } << place[x & 3u];
          brick.GroupMass[group + x / 4] += mu[x];
        }
      }
    }
  }
  // Each brick's own sums, here while it is in the cache; FirstVoxel holds its count of non-air voxels until
  // KeepNonEmptyBricks() makes it a prefix.
  for (uint64_t bx = 0; bx < bricks; ++bx)
  {
    TBrick & brick = plane[rankInPlane[bx]];
    for (unsigned int g = 0; g < 8; ++g)
    {
      brick.FirstVoxel += uint64_t{ DRRPopCount64(brick.Occupancy[g]) };
      brick.Mass += brick.GroupMass[g];
      brick.LastGroup = brick.Occupancy[g] ? static_cast<uint8_t>(g) : brick.LastGroup;
    }
  }
}

/** Moves the non-empty bricks of the grid down in curve order (in place: a copy would hold the bricks twice, 1.4 GB on
 * a 4.6 G voxel CT) and drops the rest; counts the non-air voxels before each and sums the masses in that order. */
template <typename TBrick>
void
KeepNonEmptyBricks(std::vector<TBrick> & grid, uint64_t & numberOfVoxels, double & totalMass)
{
  uint64_t numberOfBricks = 0;
  numberOfVoxels = 0;
  totalMass = 0.0;
  for (uint64_t g = 0; g < grid.size(); ++g)
  {
    TBrick &       brick = grid[g];
    const uint64_t voxels = brick.FirstVoxel;
    if (voxels == 0)
    {
      continue; // no occupancy bit: an empty brick
    }
    brick.FirstVoxel = numberOfVoxels;
    numberOfVoxels += voxels;
    totalMass += brick.Mass;
    if (numberOfBricks != g)
    {
      grid[numberOfBricks] = brick;
    }
    ++numberOfBricks;
  }
  grid.resize(numberOfBricks);
  if (grid.capacity() > numberOfBricks + numberOfBricks / 8)
  {
    grid.shrink_to_fit(); // many empty bricks (a CT of mostly air): worth the copy of the rest
  }
}
} // namespace

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

struct DRRStratifiedSampler::BrickGrid
{
  DRRAttenuationVolume::SizeType Size;
  std::array<uint64_t, 3>        BricksPerAxis;
  std::vector<uint32_t>          Rank;   // RankInPlane() of a plane of bricks
  std::vector<Brick>             Bricks; // planes of bricks in z, each in curve order; becomes m_Bricks

  /** Fills the bricks of row (by, bz) from rowOf(y, z) (BuildBrickRow()). */
  template <typename TRowOf>
  void
  FillBrickRow(uint64_t by, uint64_t bz, TRowOf && rowOf)
  {
    BuildBrickRow(Size,
                  by,
                  bz,
                  Rank.data() + by * BricksPerAxis[0],
                  Bricks.data() + bz * BricksPerAxis[0] * BricksPerAxis[1],
                  rowOf);
  }
};

DRRStratifiedSampler::BrickGrid
DRRStratifiedSampler::StartTables(const DRRAttenuationVolume::SizeType & size)
{
  m_Bricks = {}; // the last volume's bricks go before this one's are built
  m_WholeVolumePlan = nullptr;
  m_Volume = nullptr;
  BrickGrid grid;
  grid.Size = size;
  for (unsigned int a = 0; a < 3; ++a)
  {
    grid.BricksPerAxis[a] = (size[a] + brickSide - 1) / brickSide;
    if (grid.BricksPerAxis[a] > std::numeric_limits<uint16_t>::max())
    {
      itkExceptionMacro("volumes of more than " << std::numeric_limits<uint16_t>::max() * brickSide
                                                << " voxels along an axis are not supported (got " << size[a] << ")");
    }
  }
  // Every brick written straight to its place on the curve (planes of bricks in z, each in the Morton order of
  // RankInPlane()): no sort of the bricks and no second array of them.
  grid.Rank = RankInPlane(grid.BricksPerAxis[0], grid.BricksPerAxis[1]);
  grid.Bricks.resize(grid.BricksPerAxis[0] * grid.BricksPerAxis[1] * grid.BricksPerAxis[2]);
  return grid;
}

void
DRRStratifiedSampler::FinishTables(BrickGrid & grid, const DRRAttenuationVolume & volume)
{
  if (volume.GetSize() != grid.Size)
  {
    itkExceptionMacro("the tables were made for a grid of " << grid.Size[0] << " x " << grid.Size[1] << " x "
                                                            << grid.Size[2] << " voxels, not the volume's");
  }
  m_Volume = &volume;
  m_Size = grid.Size;
  m_VoxelVolume = volume.GetVoxelVolume();
  double totalMass = 0.0;
  KeepNonEmptyBricks(grid.Bricks, m_NumberOfNonAirVoxels, totalMass);
  m_Bricks = std::move(grid.Bricks);
  m_TotalMass = totalMass * m_VoxelVolume;
  m_MaximumWeight = 1.0;
  m_WholeVolumePlan =
    std::static_pointer_cast<const ViewPlan>(this->MakeSlabViewPlan(nullptr, 0.0, 0.0, SlabPlacement()));
  this->Modified();
}

void
DRRStratifiedSampler::Initialize(const DRRAttenuationVolume & volume)
{
  // One row of bricks (fixed y and z) per block, reading whole voxel rows: occupancy, group masses and each brick's
  // sums. The sampler keeps no mu: the walk reads a group's voxels from the volume when it reaches it (FillGroupMu()).
  BrickGrid      grid = this->StartTables(volume.GetSize());
  const uint64_t rowsAlongY = grid.BricksPerAxis[1];
  DRRAttenuationVolume::ParallelizeBlocks(
    rowsAlongY * grid.BricksPerAxis[2],
    [&](uint64_t brickRow) {
      std::vector<float> line(grid.Size[0]);
      grid.FillBrickRow(brickRow % rowsAlongY, brickRow / rowsAlongY, [&](uint64_t y, uint64_t z) {
        volume.FillMuRow(0, y, z, grid.Size[0], line.data());
        return line.data();
      });
    },
    nullptr);
  this->FinishTables(grid, volume);
}

void
DRRStratifiedSampler::InitializeWithControlVariate(DRRControlVariate &          controlVariate,
                                                   const DRRAttenuationVolume & volume,
                                                   unsigned int                 factor,
                                                   MultiThreaderBase *          threader)
{
  // The residual's rows come in sets of whole rows of bricks, each set once: its bricks are filled as Initialize()
  // fills them, from the rows the split has just computed.
  BrickGrid grid = this->StartTables(DRRControlVariate::ComputeResidualSize(volume.GetSize(), factor));
  controlVariate.Build(volume, factor, threader, [&grid](const DRRControlVariate::ResidualRows & rows) {
    for (uint64_t bz = rows.FirstPlane / brickSide; bz * brickSide < rows.FirstPlane + rows.NumberOfPlanes; ++bz)
    {
      for (uint64_t by = rows.FirstRow / brickSide; by * brickSide < rows.FirstRow + rows.NumberOfRows; ++by)
      {
        grid.FillBrickRow(by, bz, [&rows](uint64_t y, uint64_t z) {
          return rows.Mu + rows.Width * (y - rows.FirstRow + rows.NumberOfRows * (z - rows.FirstPlane));
        });
      }
    }
  });
  this->FinishTables(grid, controlVariate.GetResidualVolume());
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
