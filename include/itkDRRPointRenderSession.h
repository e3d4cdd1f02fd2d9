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
#ifndef itkDRRPointRenderSession_h
#define itkDRRPointRenderSession_h

#include "itkDRRCompatibility.h"
#include "itkDRRAttenuationVolume.h"
#include "itkDRREstimatorChoice.h"
#include "itkDRRPassCombination.h"
#include "itkDRRPointCloud.h"
#include "itkDRRPointProjection.h"
#include "itkDRRPointRenderer.h"
#include "itkDRRPointSampler.h"
#include "PointBasedDRRExport.h"

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <tuple>

namespace itk
{
class DRRControlVariate;

/** \class DRRPointRenderSession
 * \brief What PointBasedDRRImageFilter's renders are made of, and the renders themselves: the compiled engine the
 * filter holds through one pointer.
 *
 * The filter keeps its settings and asks the session, as DRRPointRenderer::Render() is asked: a Request (the settings),
 * the attenuation volume and its projection, or the volume's slabs (streaming). The session holds what the renders are
 * made of, each kept while nothing it was made from changed (the pipeline's modified times, and the settings it was
 * made with):
 * - the control variate's split of the volume (DRRControlVariate), or the decline of `auto`;
 * - the sampler's tables of the volume sampled (the volume, or the split's residual);
 * - the kept points (ReusePoints), drawn from the whole volume or slab by slab, with the coarse volume of a streamed
 *   draw;
 * - the passes of the last render and the refinements since (DRRPassCombination), and the pass a Refine() asks for.
 *
 * Every pass's settings are made in one place (MakePassSettings()): pass 0 is keyed by the seed itself, later ones by
 * a mix of seed and pass. The images are those the filter rendered before the session existed, bit for bit.
 *
 * \sa PointBasedDRRImageFilter, DRRPointRenderer, DRRControlVariate, DRRStreamedPointRender
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPointRenderSession
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRPointRenderSession);

  DRRPointRenderSession();
  ~DRRPointRenderSession();

  /** What a render asks for: the point filter's settings. */
  struct Request
  {
    /** Points, seed (of the render: the passes derive theirs), kernel, splat, weighting and strata. */
    DRRPointRenderer::Settings Settings;
    /** The sampler (its tables are the session's to make). */
    DRRPointSampler * Sampler{ nullptr };
    /** 0 (off), 2 to DRRControlVariate::MaximumFactor, or DRRControlVariate::AutomaticFactor. */
    unsigned int ControlVariateFactor{ 0 };
    /** Rays per pixel side of the coarse image. */
    unsigned int ControlVariateRaysPerSide{ 1 };
    /** Off: the coarse image traces one replicate, and the standard error is zero. */
    bool ComputeStandardError{ true };
    /** Keep the points of pass 0 and re-project them while the volume and the points' settings stay. */
    bool ReusePoints{ false };
    /** Poses the kept points serve (`auto` weighs the coarse image, paid per pose, against them). */
    uint64_t ExpectedNumberOfPoses{ 1 };
    /** The relative error to reach (a fraction; 0: none), the most points it may take, and whether the estimator is
     * chosen for it (ChooseEstimator()). */
    double   TargetError{ 0.0 };
    uint64_t MaximumNumberOfSamples{ 0 }; ///< see TargetError
    bool     ChooseEstimator{ false };    ///< see TargetError

    /** The renders a choice made now serves: ExpectedNumberOfPoses for kept points, else this one. */
    uint64_t
    GetPosesServed() const
    {
      return ReusePoints ? ExpectedNumberOfPoses : 1;
    }
  };

  /** The largest residual mass M_r / M that `auto` accepts: above it the session renders without a control variate.
   * At 0.5 the points' error (which scales by about M_r / M) at most halves, which the coarse image's rays do not pay
   * for; on CT M_r / M is 0.07 to 0.2, on a one-slice volume above 1. */
  static constexpr double MaximumAutomaticResidualFraction = 0.5;
  /** The smallest F `auto` picks for a streamed render (docs/design.md section 16). */
  static constexpr unsigned int MinimumStreamedAutomaticFactor = 4;

  /** A volume read slab by slab: the slabs are whole z planes, read one at a time and dropped before the next. */
  struct Slabs
  {
    /** Number of slabs, 1 or more. */
    unsigned int NumberOfSlabs{ 1 };
    /** Reads slab s (0 to NumberOfSlabs - 1) and builds its attenuation model. */
    std::function<DRRAttenuationVolume::Pointer(unsigned int)> Read;
    /** The first z plane of slab s, counted from the whole volume's first. */
    std::function<uint64_t(unsigned int)> FirstPlane;
    /** The whole volume's grid (no voxels: index-to-physical matrix and first voxel). */
    DRRAttenuationVolume::ConstPointer Grid;
    /** The whole volume's size, voxels. */
    std::array<uint64_t, 3> WholeSize{ { 0, 0, 0 } };
    /** The newest modified time of what the slabs are made of (the input's pipeline, the transfer function). */
    ModifiedTimeType MadeOf{ 0 };
  };

  /** Starts a pass: the one a Refine() asked for (RequestRefinement()), or a render's first, which clears the passes.
   * Returns its number of points: the refinement's, or renderSamples. */
  uint64_t
  BeginPass(uint64_t renderSamples);

  /** Renders the pass begun, of samples points, from the whole volume seen through projection (the volume's): the
   * kept points re-projected (drawn first if they are stale) for pass 0 with ReusePoints, points drawn anew
   * otherwise, plus the control variate's coarse image. Progress goes to caller, which is checked for abort. */
  DRRPointRenderer::Result
  Render(const Request &              request,
         uint64_t                     samples,
         const DRRAttenuationVolume & volume,
         const DRRPointProjection &   projection,
         MultiThreaderBase *          threader,
         ProcessObject *              caller);

  /** The same, from a volume read slab by slab (docs/design.md section 16): projection is the whole grid's. */
  DRRPointRenderer::Result
  Render(const Request &            request,
         uint64_t                   samples,
         const Slabs &              slabs,
         const DRRPointProjection & projection,
         MultiThreaderBase *        threader,
         ProcessObject *            caller);

  /** Adds the pass rendered to the passes; returns their combined estimate. */
  DRRPassCombination::Estimate
  AddPass(const DRRPointRenderer::Result & pass, uint64_t samples);

  /** Asks for a refinement of samples points, rendered by the next BeginPass(); throws if no pass was rendered, or if
   * anything upstream of the outputs changed since (pipelineTime: the outputs' pipeline modified time, newer). */
  void
  RequestRefinement(uint64_t samples, ModifiedTimeType pipelineTime);
  /** Drops a refinement asked for (its update failed). */
  void
  CancelRefinement()
  {
    m_RefinementSamples = 0;
  }
  /** The points of the refinement asked for; 0: the next update renders afresh. */
  uint64_t
  GetRefinementSamples() const
  {
    return m_RefinementSamples;
  }

  /** The fastest estimator of the view of projection to the request's target (DRREstimatorChoice: a pilot of the
   * view, then the cost model). With ReusePoints the choice made at the first pose is kept while the volume, the
   * target, the poses and the kernel stay: the poses of a registration render alike, and a metric whose estimator
   * changed with the pose would jump. */
  const DRREstimatorChoice::Candidate &
  ChooseEstimator(const Request &              request,
                  const DRRAttenuationVolume & volume,
                  const DRRPointProjection &   projection,
                  MultiThreaderBase *          threader);
  /** The fastest estimator to the request's target over the views pilots measured (DRREstimatorChoice::Measure(),
   * AddViews()): a batch's, chosen once for all of its views. Kept as ChooseEstimator()'s choice is, so that the
   * renders of the views keep it. */
  const DRREstimatorChoice::Candidate &
  ChooseEstimator(const Request & request, const DRRAttenuationVolume & volume, const DRREstimatorChoice & pilots);
  /** Makes the choice the fastest exact rays that reach the request's target, and returns it: chosen points whose
   * estimate stopped falling with their number (a control variate's coarse image has an error of its own). */
  const DRREstimatorChoice::Candidate &
  FallBackToExactRays(const Request & request);
  /** Makes the kept points of the choice (points) more: a first pose whose estimate missed the target draws again. */
  void
  RaiseChosenSamples(uint64_t samples)
  {
    m_Chosen.NumberOfSamples = samples;
  }
  /** Whether the choice kept for kept points is settled: its first render is done (the points it drew then are those
   * of every pose after it, whatever their estimates). */
  bool
  IsChoiceSettled() const
  {
    return m_ChoiceSettled;
  }
  /** Settles the choice (see IsChoiceSettled()). */
  void
  SettleChoice()
  {
    m_ChoiceSettled = true;
  }
  /** The pilot of the last choice (null before one). */
  const DRREstimatorChoice *
  GetEstimatorChoice() const
  {
    return m_Choice.get();
  }
  /** The last choice. */
  const DRREstimatorChoice::Candidate &
  GetChosenEstimator() const
  {
    return m_Chosen;
  }
  /** Every candidate of the last choice, with its predicted error and work (DRREstimatorChoice::ListCandidates()). */
  const std::vector<DRREstimatorChoice::Candidate> &
  GetEstimatorCandidates() const
  {
    return m_Candidates;
  }
  /** Renders the view with the exact rays, raysPerSide^2 per pixel, of the request's kernel: no pass (a Refine()
   * after it is refused), a standard error of zero, and the choice's predicted error as the estimated one. */
  DRRPassCombination::Estimate
  RenderExact(const Request &              request,
              unsigned int                 raysPerSide,
              const DRRAttenuationVolume & volume,
              const DRRPointProjection &   projection,
              MultiThreaderBase *          threader,
              ProcessObject *              caller);

  /** Makes the split and the sampler's tables of volume now, if anything they are made of changed. */
  void
  Prepare(const Request &              request,
          const DRRAttenuationVolume & volume,
          const DRRPointProjection &   projection,
          MultiThreaderBase *          threader);

  /** F of a streamed render of slabs for the view of projection: the request's, or `auto`'s choice, at least
   * Request::MinimumStreamedAutomaticFactor. */
  static unsigned int
  ResolveStreamedFactor(const Request &                 request,
                        const DRRAttenuationVolume &    grid,
                        const std::array<uint64_t, 3> & wholeSize,
                        const DRRPointProjection &      projection);

  /** Whether a control variate applies to the request's settings: the box kernel and the unbiased weighting (its
   * coarse image is the box model's line integral); `auto` resolves to off where it does not. */
  static bool
  ControlVariateApplies(const Request & request);

  /** Why the sampler's points cannot be drawn slab by slab (empty: they can). */
  static std::string
  WhyNotStreamable(const DRRPointSampler & sampler);

  /** True if a streamed render of the request would re-project current kept points: it reads no slab. */
  bool
  StreamedPointsAreCurrent(const Request & request, ModifiedTimeType slabsMadeOf) const;

  /** The split of the last render with one (null: none, declined or not made yet). */
  const DRRControlVariate *
  GetControlVariate() const;
  /** The kept points (null before a render with ReusePoints). */
  const DRRPointCloud *
  GetPointCloud() const
  {
    return m_PointCloud.GetPointer();
  }
  /** Draws of the kept points so far. */
  unsigned int
  GetNumberOfPointCloudDraws() const
  {
    return m_NumberOfPointCloudDraws;
  }
  /** The passes of the last render and the refinements since. */
  const DRRPassCombination &
  GetPasses() const
  {
    return m_Passes;
  }
  /** The estimated relative error of the passes combined (DRRPassCombination::ComputeRelativeError()), 0 before. */
  double
  GetEstimatedError() const
  {
    return m_EstimatedError;
  }
  /** The relative error of the last pass's coarse image alone (its rays', which no number of points lowers), in the
   * measure of GetEstimatedError(); 0 after a pass without a control variate. */
  double
  GetCoarseImageError() const
  {
    return m_CoarseImageError;
  }
  /** Attenuation mass of the volume in the room of the last pass, mm^2. */
  double
  GetTotalMass() const
  {
    return m_TotalMass;
  }

private:
  /** What kept points were drawn with: a change of any draws new ones. */
  struct DrawnWith
  {
    uint64_t                     NumberOfSamples{ 0 };
    uint64_t                     Seed{ 0 };
    DRRPointRenderer::KernelEnum Kernel{ DRRPointRenderer::KernelEnum::Box };
    uint64_t                     NumberOfStrata{ 0 };
    const DRRPointSampler *      Sampler{ nullptr };
    bool
    operator==(const DrawnWith & other) const;
  };
  static DrawnWith
  MakeDrawnWith(const Request & request, uint64_t samples);

  /** The settings of pass number `pass` of samples points, with the signs and channels of the volume sampled. */
  static DRRPointRenderer::Settings
  MakePassSettings(const Request & request, uint64_t samples, unsigned int pass, const DRRAttenuationVolume * sampled);

  /** Throws for a chosen F with channels (more than one): they render without a control variate. */
  static void
  RefuseChosenFactorForChannels(const Request & request);
  unsigned int
  ResolveFactor(const Request &              request,
                const DRRAttenuationVolume & volume,
                const DRRPointProjection &   projection) const;
  void
  PrepareControlVariate(const Request &              request,
                        const DRRAttenuationVolume & volume,
                        const DRRPointProjection &   projection,
                        MultiThreaderBase *          threader);
  void
  InitializeSampler(DRRPointSampler & sampler, const DRRAttenuationVolume & sampled);
  /** Notes the sampler's tables as made now, of sampled. */
  void
  NoteTables(const DRRPointSampler & sampler, const DRRAttenuationVolume & sampled);
  const DRRAttenuationVolume &
  GetSampledVolume() const;

  DRRPointRenderer::Result
  RenderKeptPoints(const Request &              request,
                   uint64_t                     samples,
                   const DRRAttenuationVolume & volume,
                   const DRRPointProjection &   projection,
                   MultiThreaderBase *          threader,
                   ProcessObject *              caller);
  DRRPointRenderer::Result
  RenderKeptPoints(const DRRPointRenderer::Settings & settings,
                   const DRRPointProjection &         projection,
                   MultiThreaderBase *                threader,
                   ProcessObject *                    caller);
  void
  AddCoarseImage(const DRRControlVariate &          controlVariate,
                 const Request &                    request,
                 const DRRPointRenderer::Settings & settings,
                 const DRRPointProjection &         projection,
                 MultiThreaderBase *                threader,
                 ProcessObject *                    caller,
                 DRRPointRenderer::Result &         result);

  class StreamedRender;

  // The split: of m_Volume as it was at m_VolumeTime, with F m_Factor (or F declined: m_ControlVariate null).
  DRRAttenuationVolume::ConstPointer   m_Volume;
  ModifiedTimeType                     m_VolumeTime{ 0 };
  unsigned int                         m_Factor{ 0 };
  itk::SmartPointer<DRRControlVariate> m_ControlVariate;

  // The sampler's tables: of m_TablesOf (at its time then), by m_TablesSampler (at its time after Initialize()).
  const DRRAttenuationVolume * m_TablesOf{ nullptr };
  ModifiedTimeType             m_TablesOfTime{ 0 };
  const DRRPointSampler *      m_TablesSampler{ nullptr };
  ModifiedTimeType             m_TablesSamplerTime{ 0 };
  TimeStamp                    m_TablesTime; // when they were made

  // The kept points, and the coarse volume of kept points drawn slab by slab.
  DRRPointCloud::Pointer                       m_PointCloud;
  itk::SmartPointer<DRRControlVariate>         m_StreamedControlVariate;
  bool                                         m_PointCloudStreamed{ false };
  DrawnWith                                    m_PointCloudDrawnWith;
  TimeStamp                                    m_PointCloudTime;
  unsigned int                                 m_NumberOfPointCloudDraws{ 0 };
  std::shared_ptr<DRRPointRenderer::Workspace> m_Workspace; // the renders of kept points reuse their sums

  // The passes, when they were rendered, and what a Refine() asks for.
  DRRPassCombination m_Passes;
  double             m_TotalMass{ 0.0 };
  double             m_EstimatedError{ 0.0 };
  double             m_CoarseImageError{ 0.0 }; // of the last pass's coarse image (AddCoarseImage())
  TimeStamp          m_PassesTime;
  uint64_t           m_RefinementSamples{ 0 };
  // The estimator chosen for a target: the pilot, its choice, and what it was made for (kept points keep it).
  std::unique_ptr<DRREstimatorChoice>        m_Choice;
  DRREstimatorChoice::Candidate              m_Chosen;
  std::vector<DRREstimatorChoice::Candidate> m_Candidates;
  // The volume's time, target, poses, kernel, control variate allowed, budget, seed and sampler.
  using ChoiceMadeFor =
    std::tuple<ModifiedTimeType, double, uint64_t, unsigned int, bool, uint64_t, uint64_t, const DRRPointSampler *>;
  ChoiceMadeFor m_ChoiceMadeFor;
  bool          m_ChoiceSettled{ false };
  static ChoiceMadeFor
  MakeChoiceKey(const Request & request, const DRRAttenuationVolume & volume);
};
} // namespace itk

#endif
