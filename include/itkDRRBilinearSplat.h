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
  static constexpr double       Reach = 1.0;
  static constexpr unsigned int Corners = 4;

  static void
  Locate(double column, double row, int32_t columns, int32_t rows, int32_t pixel[Corners], double share[Corners])
  {
    // Shift by one pixel so that truncation is the floor wherever a corner can land (column > -1).
    const double  c = column + 1.0;
    const double  r = row + 1.0;
    const bool    near = (c > 0.0) & (c < columns + 1.0) & (r > 0.0) & (r < rows + 1.0);
    const double  cs = near ? c : 0.0;
    const double  rs = near ? r : 0.0;
    const int32_t c0 = static_cast<int32_t>(cs) - 1;
    const int32_t r0 = static_cast<int32_t>(rs) - 1;
    const double  fc = cs - (c0 + 1.0);
    const double  fr = rs - (r0 + 1.0);
    const double  weights[4] = { (1.0 - fc) * (1.0 - fr), fc * (1.0 - fr), (1.0 - fc) * fr, fc * fr };
    for (unsigned int corner = 0; corner < 4; ++corner)
    {
      const int32_t pc = c0 + static_cast<int32_t>(corner & 1u);
      const int32_t pr = r0 + static_cast<int32_t>(corner >> 1);
      const bool    inside = near & (pc >= 0) & (pr >= 0) & (pc < columns) & (pr < rows) & (weights[corner] > 0.0);
      pixel[corner] = inside ? pc + columns * pr : -1;
      share[corner] = inside ? weights[corner] : 0.0;
    }
  }
};
} // namespace itk

#endif
