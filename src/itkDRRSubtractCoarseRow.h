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
#ifndef itkDRRSubtractCoarseRow_h
#define itkDRRSubtractCoarseRow_h

#include <cmath>
#include <cstdint>

/** \file itkDRRSubtractCoarseRow.h
 * \brief The residual |mu - mu_c| of a row of fine voxels against the block means of its coarse row: the rows a
 * residual volume computes where they are read (DRRAttenuationVolume::BuildResidual()), and those a control variate
 * hands to a sampler while it builds its coarse volume (DRRControlVariate::Build()). One function for both, so that
 * the two give the same bits.
 * \ingroup PointBasedDRR
 */

namespace itk
{
namespace detail
{
/** out[x] = |out[x] - coarseRow[(first + x) / factor]| for the count fine voxels first .. first + count - 1 of a row,
 * given first's coarse column (first / factor) and its place in it (first % factor). Whole blocks of the usual factors
 * (2, 4, 8, 16) in loops of fixed length, which the compiler vectorizes; else a column counter (no division per voxel).
 *
 * In float: the same bits as the difference in double rounded to float (FillResidualRow()'s r), since rounding to a
 * double (53 bits) and then to a float (24 bits) is rounding to a float once whenever 53 >= 2 * 24 + 2 (Figueroa,
 * "When is double rounding innocuous?", 1995), and |x| is exact. Four floats per instruction instead of two doubles. */
template <uint64_t TFactor>
inline void
SubtractWholeBlocks(const float * coarse, uint64_t blocks, float * out)
{
  for (uint64_t q = 0; q < blocks; ++q)
  {
    const float c = coarse[q];
    for (uint64_t t = 0; t < TFactor; ++t)
    {
      out[TFactor * q + t] = std::abs(out[TFactor * q + t] - c);
    }
  }
}

inline void
SubtractCoarseRow(const float * coarseRow,
                  uint64_t      factor,
                  uint64_t      column,
                  uint64_t      within,
                  uint64_t      count,
                  float *       out)
{
  uint64_t   x = 0;
  const auto subtractOne = [&]() {
    out[x] = std::abs(out[x] - coarseRow[column]);
    ++x;
    if (++within == factor)
    {
      within = 0;
      ++column;
    }
  };
  while (x < count && within != 0)
  {
    subtractOne(); // the head of a block begun before the row's first voxel
  }
  const uint64_t blocks = (count - x) / factor;
  bool           whole = true;
  switch (factor)
  {
    case 2:
      SubtractWholeBlocks<2>(coarseRow + column, blocks, out + x);
      break;
    case 4:
      SubtractWholeBlocks<4>(coarseRow + column, blocks, out + x);
      break;
    case 8:
      SubtractWholeBlocks<8>(coarseRow + column, blocks, out + x);
      break;
    case 16:
      SubtractWholeBlocks<16>(coarseRow + column, blocks, out + x);
      break;
    default:
      whole = false; // the counter below takes every voxel
      break;
  }
  if (whole)
  {
    x += blocks * factor;
    column += blocks;
  }
  while (x < count)
  {
    subtractOne();
  }
}
} // namespace detail
} // namespace itk

#endif
