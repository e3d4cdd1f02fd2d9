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
  template <typename TAdd>
  static bool
  Deposit(double column, double row, double weight, int64_t columns, int64_t rows, TAdd && add)
  {
    const double c0 = std::floor(column);
    const double r0 = std::floor(row);
    if (c0 < -1.0 || r0 < -1.0 || c0 >= static_cast<double>(columns) || r0 >= static_cast<double>(rows))
    {
      return false;
    }
    const double  fc = column - c0;
    const double  fr = row - r0;
    const int64_t ic = static_cast<int64_t>(c0);
    const int64_t ir = static_cast<int64_t>(r0);
    const double  shares[4] = { (1.0 - fc) * (1.0 - fr), fc * (1.0 - fr), (1.0 - fc) * fr, fc * fr };
    bool          landed = false;
    for (unsigned int corner = 0; corner < 4; ++corner)
    {
      const int64_t pc = ic + (corner & 1u);
      const int64_t pr = ir + (corner >> 1);
      if (pc >= 0 && pr >= 0 && pc < columns && pr < rows && shares[corner] > 0.0)
      {
        add(pc + columns * pr, weight * shares[corner]);
        landed = true;
      }
    }
    return landed;
  }
};
} // namespace itk

#endif
