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
#ifndef pbdrrBatchAccuracy_h
#define pbdrrBatchAccuracy_h

// --accuracy over a batch of views (issue 41): the estimator chosen over the pilots of probe views, kept points probed
// at them.

#include "pbdrrApplication.h"
#include "itkDRRRefinementTrend.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <string>

namespace pbdrr
{
/** Views of a batch whose kept points' estimates --accuracy checks before the batch: spread over it, view 0 first. */
constexpr uint64_t AccuracyProbeViews = 8;

/** --accuracy over kept points: the estimator is chosen over the pilots of AccuracyProbeViews views spread over the
 * views, view 0 first (views differ: a lateral view of a chest has more error, and its exact rays cost more, than the
 * AP one). Chosen points are fixed (F) and probed first: a quarter of the points predicted, drawn once and re-projected
 * at the probe views; then all of them are drawn, as many as the largest estimate of the probes asks and a tenth more,
 * and checked again at the probes (drawn again if they still miss; exact rays instead if the estimate stalls). The
 * views then re-project them without a standard error (the coarse image traces one replicate of rays, half of them)
 * unless its doubled variance would lift the largest estimate over the target. The probes are the same views in every
 * run and shard, so the images are too. Exact rays, chosen, trace every view alike. setView(k) sets the filter to view
 * k of the views. Returns the largest estimate of the probes (the pilots' for exact rays). */
template <typename TVolume>
double
FixAccuracy(const Renderer<TVolume> & renderer, uint64_t views, const std::function<void(uint64_t)> & setView)
{
  auto &         points = *renderer.Points;
  const uint64_t probes = std::min<uint64_t>(AccuracyProbeViews, views);
  // The choice over the probes' pilots: their errors and their rays' work differ (a lateral ray costs more).
  setView(0);
  itk::DRREstimatorChoice pilots = points.MeasureEstimatorChoice();
  for (uint64_t p = 1; p < probes; ++p)
  {
    setView(p * views / probes);
    pilots.AddViews(points.MeasureEstimatorChoice());
  }
  setView(0);
  const itk::DRREstimatorChoice::Candidate chosen = points.MakeEstimatorChoice(pilots);
  if (chosen.Kind != itk::DRREstimatorChoice::Estimator::Points)
  {
    return chosen.Error;
  }
  const double target = points.GetTargetError();
  points.SetChooseEstimator(false);
  points.SetTargetError(0.0); // the probes measure the kept points alone
  points.SetControlVariateFactor(chosen.ControlVariateFactor);
  points.SetNumberOfSamples(std::max<uint64_t>(chosen.NumberOfSamples / 4, 4096));
  double                  largest = 0.0;
  double                  largestCoarse = 0.0;   // the largest part of an estimate that is the coarse image's
  double                  coarseOfLargest = 0.0; // that part of the largest estimate
  itk::DRRRefinementTrend trend;                 // of the largest estimate of each draw
  for (unsigned int draw = 0; draw < 4; ++draw)
  {
    largest = 0.0;
    largestCoarse = 0.0;
    for (uint64_t p = 0; p < probes; ++p)
    {
      setView(p * views / probes);
      renderer.Filter->Update();
      if (points.GetEstimatedError() > largest)
      {
        largest = points.GetEstimatedError();
        coarseOfLargest = points.GetCoarseImageError();
      }
      largestCoarse = std::max(largestCoarse, points.GetCoarseImageError());
    }
    if (largest <= target && draw > 0)
    {
      break;
    }
    // The probe draw (a quarter) sets the number; a draw of all that still misses is raised the same way.
    const double more = itk::DRRRefinementTrend::GetGrowthToTarget(largest, coarseOfLargest, target);
    if (trend.AddEstimate(static_cast<double>(points.GetNumberOfSamples()), largest) || !std::isfinite(more))
    {
      // Stalled, or the coarse image's rays near the target alone, as the filter says of its own points. The exact
      // rays instead.
      points.SetTargetError(target);
      points.SetChooseEstimator(true);
      return points.FallBackToExactRays().Error;
    }
    points.SetNumberOfSamples(
      static_cast<uint64_t>(std::ceil(more * static_cast<double>(points.GetNumberOfSamples()))));
  }
  // Without a standard error the coarse image traces one replicate of its rays where the probes traced two: its
  // variance doubles. Kept at two where that would lift the largest estimate over the target (a fine F near 0.25%).
  if (largest * largest + largestCoarse * largestCoarse <= target * target)
  {
    points.SetComputeStandardError(false);
  }
  return largest;
}

/** -v's lines of --accuracy over a batch of `views` views, `selected` of them rendered: the choice (PrintAccuracy()),
 * the kept points fixed by FixAccuracy(), and the largest estimate (of the probes for kept points; of the views
 * rendered otherwise). */
template <typename TFilter>
void
PrintBatchAccuracy(const Options & options, const TFilter & points, size_t selected, uint64_t views, double largest)
{
  const uint64_t probes = std::min<uint64_t>(AccuracyProbeViews, views);
  PrintAccuracy(points, *options.accuracyPercent);
  if (!points.GetChooseEstimator())
  {
    std::cerr << "pbdrr: accuracy: kept points " << points.GetNumberOfSamples() << " for every view, checked at "
              << probes << " views spread over the batch" << std::endl;
  }
  std::cerr << "pbdrr: accuracy: the largest estimated error of the "
            << (points.GetChooseEstimator() || options.independentViews ? std::to_string(selected) + " views "
                                                                        : std::to_string(probes) + " probed views ")
            << 100.0 * largest << "% (asked " << *options.accuracyPercent << "%)" << std::endl;
}
} // namespace pbdrr

#endif
