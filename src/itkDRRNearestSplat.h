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
#ifndef itkDRRNearestSplat_h
#define itkDRRNearestSplat_h

#include "itkPointBasedDRREnums.h"

#include <cstdint>

namespace itk
{
/** \class DRRNearestSplat
 * \brief Splat policy: the whole point goes to the pixel that contains it (unbiased for the pixel-area average).
 *
 * A splat policy provides who it is (Id, its enumerator; Name, its registered name), Reach (how far
 * from a point, in pixels, the pixel centres it reaches can be), Corners (how many pixels a point can reach) and
 * Locate(column, row, columns, rows, pixel, share): for each corner the pixel index (columns fastest) and the share of
 * the point's weight, or pixel -1 and share 0 off the detector. Locate() must be branch-free (selects, no early exits)
 * so that the renderer's loop over a batch vectorizes. A new splat is its own header, an enumerator in
 * PointBasedDRREnums::Splat and one line in DRRPolicies::Splats (itkDRRPolicies.h).
 *
 * \ingroup PointBasedDRR
 */
struct DRRNearestSplat
{
  /** The enumerator that selects this splat. */
  static constexpr PointBasedDRREnums::Splat Id = PointBasedDRREnums::Splat::Nearest;
  /** Its name: the enumerator prints as its CamelCase (DRRPolicyList::GetEnumeratorName()). */
  static constexpr const char * Name = "nearest";

  /** The pixel centre a point reaches is at most half a pixel away from it along each axis. */
  static constexpr double Reach = 0.5;
  /** A point goes to one pixel. */
  static constexpr unsigned int Corners = 1;

  /** Offset (pixels, along one axis) from a pixel centre of a detector position drawn from the pixel's footprint for
   * this splat, the density with which a position counts to the pixel (uniform over the pixel), for u uniform in
   * [0, 1): the rays of the control variate's exact coarse image (DRRExactRayIntegrator::RenderFootprintAverages()). */
  static double
  FootprintOffset(double u)
  {
    return u - 0.5;
  }

  /** The pixel that contains (column, row) (continuous pixel indices, centres at integers), with share 1; pixel -1
   * and share 0 off the detector. TReal: double (the render that draws), or float (the render of a kept cloud, twice
   * the lanes). */
  template <typename TReal>
  static void
  Locate(TReal column, TReal row, int32_t columns, int32_t rows, int32_t pixel[Corners], TReal share[Corners])
  {
    const TReal c = column + TReal(0.5);
    const TReal r = row + TReal(0.5);
    const bool  inside = (c >= TReal(0)) & (c < TReal(columns)) & (r >= TReal(0)) & (r < TReal(rows));
    // Truncation is the floor on the detector; off it, convert a harmless 0 instead (no undefined conversion).
    pixel[0] =
      inside ? static_cast<int32_t>(inside ? c : TReal(0)) + columns * static_cast<int32_t>(inside ? r : TReal(0)) : -1;
    share[0] = inside ? TReal(1) : TReal(0);
  }
};
} // namespace itk

#endif
