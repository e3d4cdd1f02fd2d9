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
#ifndef itkDRRPointSplatter_h
#define itkDRRPointSplatter_h

// Private to the renderer (src/): the projection and splat of points into the fixed-point sums, header-only so that
// it is inlined into the vector clones of the chunk loops (itkDRRPointRenderer.cxx).

#include "itkDRRRenderWorkers.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace itk
{
namespace DRRRendering
{
/** Projects points and adds them to the fixed-point sums. One instantiation per splat, and per precision of the
 * points (double for a render that draws them, float for the render of a kept cloud): the same steps either way. */
template <typename TSplat>
class PointSplatter
{
public:
  PointSplatter(const DRRPointProjection & projection, const FixedPoint & fixedPoint, bool unbiased)
    : m_Projection(projection)
    , m_Columns(static_cast<int32_t>(projection.GetNumberOfColumns()))
    , m_Rows(static_cast<int32_t>(projection.GetNumberOfRows()))
    , m_SumScale(std::ldexp(1.0, fixedPoint.SumExponent))
    , m_SquareScale(std::ldexp(1.0, fixedPoint.SquareExponent))
    , m_SmallFixedPoint(fixedPoint.Small)
    , m_Unbiased(unbiased)
  {}

  /** Projects count points (continuous indices x, y, z, sampler weights, strata) and adds each to the fixed-point sums
   * of its stratum (and to the sums of squares, with one stratum): first the sum index and fixed-point value of every
   * corner (a loop that vectorizes), then the additions. A corner off the detector goes to the trash slot past the
   * pixels' sums (with value 0): the additions need no branch. */
  template <typename TReal, typename TStratum>
  inline void
  ProjectAndSplat(uint64_t            count,
                  const TReal *       x,
                  const TReal *       y,
                  const TReal *       z,
                  const TReal *       weight,
                  const TStratum *    stratum,
                  SplatBatch<TReal> & batch,
                  uint64_t            numberOfStrata,
                  Accumulator &       sums) const
  {
    m_Projection.ProjectBatch(count, x, y, z, batch.Column, batch.Row, batch.Perspective);
    const bool squares = !sums.SumOfSquares.empty();
    const auto strata = static_cast<int32_t>(numberOfStrata);
    uint64_t   landed;
    // One loop per case, each free of calls and branches, so that it vectorizes.
    if (m_SmallFixedPoint)
    {
      landed = squares ? this->PrepareCorners<true, true>(count, weight, stratum, strata, batch)
                       : this->PrepareCorners<true, false>(count, weight, stratum, strata, batch);
    }
    else
    {
      landed = squares ? this->PrepareCorners<false, true>(count, weight, stratum, strata, batch)
                       : this->PrepareCorners<false, false>(count, weight, stratum, strata, batch);
    }
    sums.PointsOnDetector += landed;
    int64_t * sum = sums.Sum.data();
    for (unsigned int c = 0; c < TSplat::Corners; ++c)
    {
      Scatter(sum, batch.Index + c * samplesPerBatch, batch.Value + c * samplesPerBatch, count);
    }
    if (squares)
    {
      // One stratum: the index of a sum is its pixel's.
      for (unsigned int c = 0; c < TSplat::Corners; ++c)
      {
        Scatter(sums.SumOfSquares.data(), batch.Index + c * samplesPerBatch, batch.Square + c * samplesPerBatch, count);
      }
    }
  }

private:
  /** sum[index[s]] += value[s] for s < count, in four interleaved streams a quarter of the batch apart. Nearby points
   * often add to the same sum: in one stream, each addition would wait for the previous one's store; points a quarter
   * batch apart rarely share a pixel. Integer sums: the order changes nothing. */
  static void
  Scatter(int64_t * sum, const int32_t * index, const int64_t * value, uint64_t count)
  {
    const uint64_t quarter = count / 4;
    for (uint64_t s = 0; s < quarter; ++s)
    {
      sum[index[s]] += value[s];
      sum[index[s + quarter]] += value[s + quarter];
      sum[index[s + 2 * quarter]] += value[s + 2 * quarter];
      sum[index[s + 3 * quarter]] += value[s + 3 * quarter];
    }
    for (uint64_t s = 4 * quarter; s < count; ++s)
    {
      sum[index[s]] += value[s];
    }
  }

  /** The sum index and fixed-point value (and square) of every corner of every point of a batch; returns the number of
   * points that reach the detector. The contribution is rounded to TReal, then scaled exactly (the scales are powers
   * of two) and rounded to fixed point in double; its square is exact in double when TReal is float. */
  template <bool VSmall, bool VSquares, typename TReal, typename TStratum>
  inline uint64_t
  PrepareCorners(uint64_t            count,
                 const TReal *       pointWeight,
                 const TStratum *    stratum,
                 int32_t             strata,
                 SplatBatch<TReal> & batch) const
  {
    constexpr unsigned int corners = TSplat::Corners;
    static_assert(corners <= maximumCorners, "SplatBatch holds at most maximumCorners corners per point");
    const bool    unbiased = m_Unbiased;
    const double  sumScale = m_SumScale;
    const double  squareScale = m_SquareScale;
    const int32_t columns = m_Columns;
    const int32_t rows = m_Rows;
    const int32_t trash = columns * rows * strata;
    // Widened in a loop of its own: bytes in the loop below keep it from vectorizing for AVX-512F (no byte vectors).
    for (uint64_t s = 0; s < count; ++s)
    {
      batch.Stratum[s] = static_cast<int32_t>(stratum[s]);
    }
    // Without the perspective weight, a factor 1 (exact): a select on unbiased in the loop below would not vectorize.
    if (!unbiased)
    {
      std::fill(batch.Perspective, batch.Perspective + count, TReal(1));
    }
    for (uint64_t s = 0; s < count; ++s)
    {
      // A point that does not count lands off the detector (and has perspective weight 0). Every load unconditional,
      // so that the selects need no branch.
      const TReal   ownWeight = pointWeight[s];
      const TReal   perspective = batch.Perspective[s];
      const TReal   weight = ownWeight * perspective;
      const int32_t ownStratum = batch.Stratum[s];
      int32_t       pixel[corners];
      TReal         share[corners];
      TSplat::Locate(batch.Column[s], batch.Row[s], columns, rows, pixel, share);
      for (unsigned int c = 0; c < corners; ++c)
      {
        const double contribution = static_cast<double>(weight * share[c]);
        batch.Index[c * samplesPerBatch + s] = pixel[c] >= 0 ? pixel[c] * strata + ownStratum : trash;
        batch.Value[c * samplesPerBatch + s] = Round<VSmall>(contribution * sumScale);
        batch.Square[c * samplesPerBatch + s] = VSquares ? Round<VSmall>(contribution * contribution * squareScale) : 0;
      }
    }
    // Counted in a loop of its own, from the indices: in the loop above, the count (or a test of the pixels) would
    // stop it from vectorizing.
    int32_t landed = 0;
    for (uint64_t s = 0; s < count; ++s)
    {
      int32_t reached = 0;
      for (unsigned int c = 0; c < corners; ++c)
      {
        reached |= static_cast<int32_t>(batch.Index[c * samplesPerBatch + s] != trash);
      }
      landed += reached;
    }
    return static_cast<uint64_t>(landed);
  }

  /** llrint(x). For |x| < 2^51 (VSmall): adding 1.5 2^52 rounds to the nearest integer (ties to even, as llrint) in
   * the low mantissa bits; this form vectorizes. */
  template <bool VSmall>
  static int64_t
  Round(double x)
  {
    if (VSmall)
    {
      const double shifted = x + 6755399441055744.0;
      int64_t      bits;
      std::memcpy(&bits, &shifted, sizeof(bits));
      return bits - 0x4338000000000000;
    }
    return std::llrint(x);
  }

  const DRRPointProjection & m_Projection;
  const int32_t              m_Columns;
  const int32_t              m_Rows;
  const double               m_SumScale;
  const double               m_SquareScale;
  const bool                 m_SmallFixedPoint;
  const bool                 m_Unbiased;
};
} // namespace DRRRendering
} // namespace itk

#endif
