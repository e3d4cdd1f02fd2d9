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
#ifndef itkDRROutputConversion_h
#define itkDRROutputConversion_h

#include "itkPointBasedDRREnums.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <vector>

namespace itk
{
/** \class DRROutputConversion
 * \brief From a line integral L to the value an output mode stores, and the slope d(value)/dL that carries a
 * standard error through the mode (delta method).
 *
 * LineIntegral: L, slope 1. Transmission: exp(-L), slope exp(-L). Gray8 / Gray16: the window [level - width / 2,
 * level + width / 2] mapped onto 0 .. 255 or 0 .. 65535 and rounded, bright = attenuating; slope levels per unit of L
 * inside the window, 0 where clamped.
 *
 * \sa DRRImageFilterBase::SetOutputMode()
 * \ingroup PointBasedDRR
 */
class DRROutputConversion
{
public:
  /** What the output pixels hold. */
  using OutputModeEnum = PointBasedDRREnums::OutputMode;

  /** The gray window starts at windowLow (= level - width / 2) and spans width > 0 (unused by the other modes). */
  DRROutputConversion(OutputModeEnum mode, double windowLow, double width)
    : m_Mode(mode), m_Low(windowLow), m_Width(width), m_Maximum(mode == OutputModeEnum::Gray8 ? 255.0 : 65535.0)
  {}

  /** The automatic gray window of a line-integral image [first, last): from its 0.5th to its 99.5th percentile (the
   * values at indices floor(q (n - 1)) of its sorted values), so that a few extreme pixels (metal, the edge of the
   * volume) do not take the gray levels; width at least 1e-6 (a flat image). The one rule of the filters' Gray8 and
   * Gray16 without a window (WindowWidth 0) and of pbdrr's gray outputs. */
  template <typename TIterator>
  static void
  ComputeAutomaticWindow(TIterator first, TIterator last, double & windowLow, double & width)
  {
    std::vector<typename std::iterator_traits<TIterator>::value_type> values(first, last);
    if (values.empty())
    {
      windowLow = 0.0;
      width = 1.0;
      return;
    }
    const auto at = [&values](double quantile) {
      const auto k = values.begin() + static_cast<std::ptrdiff_t>(quantile * static_cast<double>(values.size() - 1));
      std::nth_element(values.begin(), k, values.end());
      return static_cast<double>(*k);
    };
    const double low = at(0.005);
    const double high = at(0.995);
    windowLow = low;
    width = std::max(high - low, 1e-6);
  }

  /** True for Gray8 and Gray16. */
  bool
  IsGray() const
  {
    return m_Mode == OutputModeEnum::Gray8 || m_Mode == OutputModeEnum::Gray16;
  }
  /** Largest gray level. */
  double
  GetMaximum() const
  {
    return m_Maximum;
  }

  /** The value the mode stores for a line integral L: L, exp(-L), or a gray level (rounded, clamped to the window). */
  double
  Value(double lineIntegral) const
  {
    if (m_Mode == OutputModeEnum::Transmission)
    {
      return std::exp(-lineIntegral);
    }
    if (this->IsGray())
    {
      return std::floor(std::min(1.0, std::max(0.0, this->Position(lineIntegral))) * m_Maximum + 0.5);
    }
    return lineIntegral;
  }

  /** d(value)/dL at L: 1, exp(-L), or gray levels per unit of L (0 outside the window), the factor that carries a
   * standard error of L through the mode. */
  double
  Slope(double lineIntegral) const
  {
    if (m_Mode == OutputModeEnum::Transmission)
    {
      return std::exp(-lineIntegral);
    }
    if (this->IsGray())
    {
      const double position = this->Position(lineIntegral);
      return position > 0.0 && position < 1.0 ? m_Maximum / m_Width : 0.0;
    }
    return 1.0;
  }

private:
  double
  Position(double lineIntegral) const
  {
    return (lineIntegral - m_Low) / m_Width;
  }

  OutputModeEnum m_Mode;
  double         m_Low;
  double         m_Width;
  double         m_Maximum;
};
} // namespace itk

#endif
