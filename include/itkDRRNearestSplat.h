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

#include <cmath>
#include <cstdint>

namespace itk
{
/** \class DRRNearestSplat
 * \brief Splat policy: the whole point goes to the pixel that contains it (unbiased for the pixel-area average).
 *
 * A splat policy provides Deposit(column, row, weight, columns, rows, add): it calls add(pixel, share of weight) for
 * every pixel the point reaches and returns whether it reached the detector. Register a new one with one case in
 * WithSplat() in itkDRRPointRenderer.cxx.
 *
 * \ingroup PointBasedDRR
 */
struct DRRNearestSplat
{
  template <typename TAdd>
  static bool
  Deposit(double column, double row, double weight, int64_t columns, int64_t rows, TAdd && add)
  {
    const double c = std::floor(column + 0.5);
    const double r = std::floor(row + 0.5);
    if (c >= 0.0 && r >= 0.0 && c < static_cast<double>(columns) && r < static_cast<double>(rows))
    {
      add(static_cast<int64_t>(c) + columns * static_cast<int64_t>(r), weight);
      return true;
    }
    return false;
  }
};
} // namespace itk

#endif
