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
#ifndef itkDRRStratifiedSamplerParts_h
#define itkDRRStratifiedSamplerParts_h

// Private to DRRStratifiedSampler (src/): what its two files share, the bricks' Morton layout and the plan of a
// render. itkDRRStratifiedSampler.cxx builds the brick tables; itkDRRStratifiedSamplerWalk.cxx plans a view or a slab
// and walks the curve.

#include "itkDRRStratifiedSampler.h"
#include "itkDRRCompilerBuiltins.h"

#include <array>
#include <cstdint>
#include <vector>

namespace itk
{
namespace DRRStratifiedBricks
{
constexpr uint64_t brickSide = 8; // voxels per brick side
constexpr uint64_t voxelsPerBrick = brickSide * brickSide * brickSide;

/** Interleaves the bits of x, y, z (x lowest): the Morton code. */
inline uint64_t
MortonCode(uint64_t x, uint64_t y, uint64_t z)
{
  uint64_t code = 0;
  for (unsigned int bit = 0; bit < 21; ++bit)
  {
    code |= ((x >> bit) & 1u) << (3 * bit) | ((y >> bit) & 1u) << (3 * bit + 1) | ((z >> bit) & 1u) << (3 * bit + 2);
  }
  return code;
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

inline const MortonInsideBrick &
GetMortonInsideBrick()
{
  static const MortonInsideBrick table;
  return table;
}

/** Voxel index (i, j, k) of the voxel at Morton position `position` (0 .. 511) of the brick whose brick coordinates are
 * origin. */
inline std::array<uint32_t, 3>
VoxelInBrick(const uint16_t origin[3], uint64_t position)
{
  const uint16_t offset = GetMortonInsideBrick().Offset[position];
  return { { static_cast<uint32_t>(origin[0] * brickSide + (offset & 7u)),
             static_cast<uint32_t>(origin[1] * brickSide + ((offset >> 3) & 7u)),
             static_cast<uint32_t>(origin[2] * brickSide + (offset >> 6)) } };
}

/** Lowest set bit. */
inline unsigned int
LowestBit(uint64_t bits)
{
  return DRRCountTrailingZeros64(bits);
}
} // namespace DRRStratifiedBricks

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
} // namespace itk

#endif
