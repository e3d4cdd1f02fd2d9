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
#ifndef itkDRRBilinearSplat_h
#define itkDRRBilinearSplat_h

#include "itkPointBasedDRREnums.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace itk
{
/** \class DRRBilinearSplat
 * \brief Splat policy: the point is shared among the four nearest pixel centres with bilinear weights. Lower variance;
 * its expectation is the pixel-area average blurred by a one-pixel tent.
 *
 * \sa DRRNearestSplat for the policy's interface.
 * \ingroup PointBasedDRR
 */
struct DRRBilinearSplat
{
  /** The enumerator that selects this splat. */
  static constexpr PointBasedDRREnums::Splat Id = PointBasedDRREnums::Splat::Bilinear;
  /** Its name: the enumerator prints as its CamelCase (DRRPolicyList::GetEnumeratorName()). */
  static constexpr const char * Name = "bilinear";

  /** The pixel centres a point reaches are less than 1 pixel away from it along each axis. */
  static constexpr double Reach = 1.0;
  /** A point is shared among up to 4 pixels. */
  static constexpr unsigned int Corners = 4;

  /** Offset (pixels, along one axis) from a pixel centre of a detector position drawn from the pixel's footprint for
   * this splat, the density with which a position counts to the pixel (the tent 1 - |x| on [-1, 1], whose integral
   * is one pixel), for u uniform in [0, 1): the inverse of the tent's distribution function. The rays of the control
   * variate's exact coarse image (DRRExactRayIntegrator::RenderFootprintAverages()). */
  static double
  FootprintOffset(double u)
  {
    return u < 0.5 ? std::sqrt(2.0 * u) - 1.0 : 1.0 - std::sqrt(2.0 * (1.0 - u));
  }

  /** The four pixels around (column, row) (continuous pixel indices, centres at integers) and their bilinear shares,
   * pixel -1 and share 0 for those off the detector. TReal: double (the render that draws), or float (the render of a
   * kept cloud, twice the lanes). */
  template <typename TReal>
  static void
  Locate(TReal column, TReal row, int32_t columns, int32_t rows, int32_t pixel[Corners], TReal share[Corners])
  {
    // Shift by one pixel so that truncation is the floor wherever a corner can land (column > -1). Clamped to
    // [0, columns + 1] (NaN to 0) rather than tested: a point in range keeps its value; a point out of range in
    // either axis gets, in that axis, either the first corner at -1 and the second with weight 0, or both corners
    // past the last pixel, so none of its corners lands. No select on a point-wide test: the vectorizer keeps the
    // loop in lanes of one width.
    const TReal   cs = std::min(TReal(columns + 1), std::max(TReal(0), column + TReal(1)));
    const TReal   rs = std::min(TReal(rows + 1), std::max(TReal(0), row + TReal(1)));
    const int32_t c0 = static_cast<int32_t>(cs) - 1;
    const int32_t r0 = static_cast<int32_t>(rs) - 1;
    const TReal   fc = cs - TReal(c0 + 1);
    const TReal   fr = rs - TReal(r0 + 1);
    const TReal weights[4] = { (TReal(1) - fc) * (TReal(1) - fr), fc * (TReal(1) - fr), (TReal(1) - fc) * fr, fc * fr };
    for (unsigned int corner = 0; corner < 4; ++corner)
    {
      const int32_t pc = c0 + static_cast<int32_t>(corner & 1u);
      const int32_t pr = r0 + static_cast<int32_t>(corner >> 1);
      const bool    inside = (pc >= 0) & (pr >= 0) & (pc < columns) & (pr < rows) & (weights[corner] > TReal(0));
      pixel[corner] = inside ? pc + columns * pr : -1;
      share[corner] = inside ? weights[corner] : TReal(0);
    }
  }
};
} // namespace itk

#endif
