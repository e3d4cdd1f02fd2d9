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
#ifndef itkDRREstimatorChoice_h
#define itkDRREstimatorChoice_h

#include "itkDRRAttenuationVolume.h"
#include "itkDRRPointProjection.h"
#include "itkMultiThreaderBase.h"
#include "PointBasedDRRExport.h"

#include <cstdint>
#include <string>
#include <vector>

namespace itk
{
/** \class DRREstimatorChoice
 * \brief The fastest estimator of a view to a stated error: exact rays (k x k per pixel), points, or points with a
 * control variate of factor F, from a pilot of the view and a cost model of CPU work.
 *
 * The error is PointBasedDRRImageFilter::SetTargetError()'s: the root mean square of the per-pixel error over the range
 * of the line-integral image (NRMSE against the exact pixel-averaged image), a fraction.
 *
 * Measure() traces a pilot: one pixel in each cell of a PilotGridSide x PilotGridSide grid of the detector (a fixed
 * stream picks it in its cell), at 1, 2, 4 and 8 x 8 rays per pixel, 85 rays a pixel. From it:
 * - the exact error of k x k rays, e_k = RMS(v_k - v_8) / (1 - k / 8) / range: the midpoint rule's error falls as
 *   1 / k at least (as 1 / k at an edge, 1 / k^2 where the image is smooth), so that v_8 keeps at most k / 8 of v_k's
 *   error, and e_k is an upper estimate; e_8 and e_16 are e_4 / 2 and e_4 / 4 on the same rule;
 * - the error of N points, e = s mean(L) sqrt(P / N) / range: the variance of a pixel of an importance-sampled sum
 *   whose points are drawn in proportion to mu is L_p M_view / (N a) (a: a pixel's area at the points), and the mass
 *   in the view M_view is the sum of L_p a, so that its mean over the P pixels is mean(L)^2 P / N; s is the sampler's
 *   ratio to it (CostModel::PointErrorScale); a control variate of factor F multiplies it by about M_r / M
 *   (CostModel::ControlVariateErrorScale2);
 * - the rays' work: the cells each pilot ray crosses, and its reads of the volume that miss the cache (the lines the
 *   ray of the pixel before did not read, off the stride of the reads before: a prefetcher follows a stride).
 *
 * The cost of each estimator is CPU work predicted from the counts (pixels, rays, cells, voxels, points, poses) and
 * the constants of CostModel, measured on this project's 2-core machine (docs/performance.md, "Ask for an
 * accuracy"; SetCostModel() takes another machine's): never a clock, so the choice, and the image, are the same on any
 * number of threads and on every run. Choose() returns the fastest candidate whose predicted error is at most the
 * target.
 *
 * \sa PointBasedDRRImageFilter::SetChooseEstimator(), DRRExactRayIntegrator
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRREstimatorChoice
{
public:
  /** Box (Siddon) or Tent (trilinear) voxel model of the exact rays. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;

  /** Exact rays (DRRExactRayIntegrator::RenderProjection()), or points (with or without a control variate). */
  enum class Estimator : uint8_t
  {
    ExactRays, ///< DRRExactRayIntegrator::RenderProjection(), k x k rays per pixel
    Points     ///< points, plain or with a control variate
  };

  /** One way to the target, with what it is predicted to cost and to reach. */
  struct Candidate
  {
    Estimator    Kind{ Estimator::Points }; ///< exact rays or points
    unsigned int RaysPerSide{ 0 };          ///< exact: k, k x k rays per pixel
    unsigned int ControlVariateFactor{ 0 }; ///< points: 0 (plain) or F
    uint64_t     NumberOfSamples{ 0 };      ///< points: N, the fewest predicted to reach the target
    double       Seconds{ 0.0 };            ///< predicted CPU seconds, every pose
    double       Error{ 0.0 };              ///< predicted relative error (a fraction)
    /** "exact 2 x 2 rays per pixel", "points 3200000", "points 800000 with control variate F 8". */
    std::string
    Describe() const;
  };

  /** CPU nanoseconds of each part of the work, and the points' error constants: measured on the LIDC chest (512 x 512
   * x 275) at 256 x 256 pixels on this project's 2-core machine (pbdrr -v's stage times on 2 threads; the exact rays at
   * 1, 2 and 8 x 8 per pixel, and at one per pixel from gantry 0 to 90 degrees in steps of 15, fitted to within 17%;
   * plain points and control variates of F 2 to 16 at 10^6 and 10^7 points). */
  struct CostModel
  {
    /** An exact ray: a fixed part (the ray's setup and clipping), a part per cell it crosses, and a part per read the
     * cache cannot serve: a cache line the ray before it in its tile did not read, off the stride of the ray's reads
     * before (DRRExactRayIntegrator::ListReadCacheLines()). A lateral ray of a CT reads its rows along x, the
     * fastest axis, and its neighbours read other rows; an AP ray's neighbours read its lines. */
    double RayNanoseconds{ 250.0 };
    /** See RayNanoseconds. */
    double CellNanoseconds{ 2.3 };
    /** See RayNanoseconds. */
    double UnforeseenMissNanoseconds{ 38.0 };
    /** The sampler's tables, per voxel of the volume (drawn once for every pose). */
    double TableNanosecondsPerVoxel{ 1.4 };
    /** The control variate's split (block means and residual), per voxel. */
    double SplitNanosecondsPerVoxel{ 0.9 };
    /** To draw and splat one point; to splat a kept point at one more pose. */
    double PointNanoseconds{ 40.0 };
    /** See PointNanoseconds. */
    double KeptPointNanoseconds{ 3.0 };
    /** Rays per pixel of the control variate's coarse image: 2 replicates of an antithetic pair at the first pose,
     * whose standard error the choice is checked with; one replicate at each pose after it (a batch's views). */
    double CoarseRaysPerPixel{ 4.0 };
    /** See CoarseRaysPerPixel. */
    double CoarseRaysPerPixelAfterTheFirstPose{ 2.0 };
    /** The sampler's error over mean(L) sqrt(P / N) / range (the stratified sampler's, on the chest and the head). */
    double PointErrorScale{ 0.8 };
    /** The control variate's error over plain points' at equal N: Scale2 (F / 2)^Exponent (0.149, 0.245, 0.32 of it at
     * F = 2, 8, 16 on the chest). */
    double ControlVariateErrorScale2{ 0.15 };
    /** See ControlVariateErrorScale2. */
    double ControlVariateErrorExponent{ 0.37 };
  };

  /** Side of the pilot's grid of pixels (16: 256 pixels, 85 rays each). */
  static constexpr unsigned int PilotGridSide = 16;
  /** Rays per pixel side the pilot traces; the last is its reference. */
  static constexpr unsigned int PilotRaysPerSide[4] = { 1, 2, 4, 8 };
  /** Exact candidates: k x k rays per pixel. */
  static constexpr unsigned int ExactRaysPerSide[5] = { 1, 2, 4, 8, 16 };
  /** Control-variate candidates: F (0: plain points). */
  static constexpr unsigned int ControlVariateFactors[5] = { 0, 2, 4, 8, 16 };

  /** Traces the pilot of projection's view of volume with kernel's exact model, on threader (not null): the same
   * numbers on any number of threads. Throws ExceptionObject for a view that sees nothing of the volume. */
  void
  Measure(const DRRAttenuationVolume & volume,
          KernelEnum                   kernel,
          const DRRPointProjection &   projection,
          MultiThreaderBase *          threader);

  /** Every candidate for target (a fraction) and poses renders of the view (kept points re-projected at each; exact
   * rays and a control variate's coarse image traced at each), each at the effort predicted to reach the target;
   * controlVariate false leaves out the control variate (a tent kernel, for one). */
  std::vector<Candidate>
  ListCandidates(double target, uint64_t poses, bool controlVariate) const;

  /** The fastest candidate of ListCandidates() whose predicted error is at most target, points of at most
   * maximumSamples. The exact candidates always reach some error, so there is one unless the target is below e_16:
   * then ExceptionObject says so. */
  Candidate
  Choose(double target, uint64_t poses, bool controlVariate, uint64_t maximumSamples) const;
  /** Choose() among candidates (ListCandidates()'s, for the same target). */
  static Candidate
  Choose(const std::vector<Candidate> & candidates, double target, uint64_t maximumSamples);
  /** The fastest of candidates whose predicted error is at most target, points of at most maximumSamples, exact rays
   * only if exactRaysOnly; null if none is. */
  static const Candidate *
  FindFastest(const std::vector<Candidate> & candidates, double target, uint64_t maximumSamples, bool exactRaysOnly);

  /** The predicted relative error of the exact rays, k x k per pixel (k one of ExactRaysPerSide). */
  double
  GetExactError(unsigned int raysPerSide) const;
  /** Predicted relative error of N points with a control variate of factor F (0: plain). */
  double
  GetPointsError(uint64_t samples, unsigned int factor) const;

  /** Adds the views other measured (Measure(), of the same detector and volume): the choice is then for poses renders
   * spread over all the views, a batch's. The errors are the largest of the views (each view must reach the target);
   * the work per ray is their mean (the views are rendered in turn). */
  void
  AddViews(const DRREstimatorChoice & other);
  /** The views measured: 1 after Measure(), more after AddViews(). */
  unsigned int
  GetNumberOfViews() const
  {
    return static_cast<unsigned int>(m_Views.size());
  }

  /** The pilot's mean line integral and range (max - min over the pilot pixels at 8 x 8 rays), dimensionless, of the
   * view measured first. */
  double
  GetMeanLineIntegral() const
  {
    return m_Views.empty() ? 0.0 : m_Views.front().MeanLineIntegral;
  }
  /** See GetMeanLineIntegral(). */
  double
  GetRange() const
  {
    return m_Views.empty() ? 0.0 : m_Views.front().Range;
  }

  /** Cells an exact ray crosses, and its reads of the volume that miss the cache (CostModel::RayNanoseconds), the
   * means over the pilot's rays and views. */
  double
  GetMeanCellsPerRay() const
  {
    return this->GetMeanOverViews(&ViewPilot::MeanCellsPerRay);
  }
  /** See GetMeanCellsPerRay(). */
  double
  GetMeanUnforeseenMissesPerRay() const
  {
    return this->GetMeanOverViews(&ViewPilot::MeanUnforeseenMissesPerRay);
  }

  /** The constants of the costs and errors (the defaults of CostModel unless set). */
  void
  SetCostModel(const CostModel & model)
  {
    m_Model = model;
  }
  /** See SetCostModel(). */
  const CostModel &
  GetCostModel() const
  {
    return m_Model;
  }

private:
  /** What the pilot of one view measured. */
  struct ViewPilot
  {
    double MeanLineIntegral{ 0.0 };
    double Range{ 0.0 };
    double ExactRms[3]{ 0.0, 0.0, 0.0 }; // RMS(v_k - v_8) for k = 1, 2, 4
    double MeanCellsPerRay{ 0.0 };
    double MeanUnforeseenMissesPerRay{ 0.0 };
    double
    GetExactError(unsigned int raysPerSide) const;
  };

  /** The mean of a count of the views' pilots (0 before Measure()). */
  double
  GetMeanOverViews(double ViewPilot::*count) const;
  /** CPU nanoseconds of an exact ray, the mean over the views: cellFraction of the cells (1 / F for a coarse volume),
   * with the cache misses or without (a coarse volume stays in the cache). */
  double
  GetRayNanoseconds(double cellFraction, bool withMisses) const;
  double
  ExactSeconds(unsigned int raysPerSide, uint64_t poses) const;
  double
  PointsSeconds(uint64_t samples, unsigned int factor, uint64_t poses) const;

  CostModel              m_Model;
  double                 m_Pixels{ 0.0 };
  double                 m_Voxels{ 0.0 };
  std::vector<ViewPilot> m_Views;
};
} // namespace itk

#endif
