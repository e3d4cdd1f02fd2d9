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
#ifndef itkDRRRefinementTrend_h
#define itkDRRRefinementTrend_h

#include <cmath>
#include <limits>

namespace itk
{
/** \class DRRRefinementTrend
 * \brief Whether an estimated error still falls with the points as 1 / sqrt(N), or has stalled: the rule by which
 * chosen points give way to exact rays (PointBasedDRRImageFilter's refinement to its TargetError, and pbdrr's batch).
 *
 * The estimate of independent points falls as 1 / sqrt(N). Part of an error may not be theirs to lower: the control
 * variate's coarse image has its own, at its fixed rays per pixel. Estimates are judged over MinimumGrowth times the
 * points at least, because the estimates of few points are noisy. Stalled: the estimate fell by less than half of what
 * 1 / sqrt(N) predicts since the last estimate judged.
 * \ingroup PointBasedDRR
 */
class DRRRefinementTrend
{
public:
  /** The growth of the points between two estimates judged. */
  static constexpr double MinimumGrowth = 1.5;
  /** The largest part of the target the control variate's coarse image may take (its error over the target's): the
   * points would have to take theirs down to sqrt(t^2 - c^2), many times more of them, beyond it. */
  static constexpr double LargestCoarseShare = 0.8;

  /** The factor by which the points must grow for an estimate of `error` (relative, a fraction) to reach `target`: the
   * points' part of its variance, error^2 - coarse^2, falls as 1 / N, the coarse image's (coarse: its error, at its
   * fixed rays per pixel) does not; a tenth more, so that an estimate a little low does not cost a pass of a few
   * points. For coarse above LargestCoarseShare of the target, infinity: not the points' to reach. */
  static double
  GetGrowthToTarget(double error, double coarse, double target)
  {
    if (coarse > LargestCoarseShare * target)
    {
      return std::numeric_limits<double>::infinity();
    }
    return 1.1 * (error * error - coarse * coarse) / (target * target - coarse * coarse);
  }

  /** Adds the estimate (relative error, a fraction) of `points` points in all; true if the estimate has stalled. */
  bool
  AddEstimate(double points, double error)
  {
    const bool   judged = m_Points == 0.0 || points >= MinimumGrowth * m_Points;
    const double expected = m_Error * std::sqrt(m_Points / points); // as 1 / sqrt(points)
    const bool   stalled = m_Points > 0.0 && judged && error - expected > 0.5 * (m_Error - expected);
    if (judged)
    {
      m_Error = error;
      m_Points = points;
    }
    return stalled;
  }

private:
  double m_Error{ 0.0 }; // the last estimate judged, and its points
  double m_Points{ 0.0 };
};
} // namespace itk

#endif
