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
#ifndef itkPointBasedDRRImageFilter_h
#define itkPointBasedDRRImageFilter_h

#include "itkDRRCompatibility.h"
#include "itkDRRImageFilterBase.h"
#include "itkDRRControlVariate.h"
#include "itkDRRPointRenderSession.h"
#include "itkDRRPointSampler.h"
#include "itkDRRPointRenderer.h"
#include "itkDRRRefinementTrend.h"

#include <memory>

namespace itk
{
/** \class PointBasedDRRImageFilter
 * \brief Renders a digitally reconstructed radiograph by Monte Carlo point sampling (Point-based DRR).
 *
 * N points are drawn with density proportional to the attenuation mu (the sampler policy picks voxels, the
 * reconstruction kernel places the point inside its voxel), projected onto the detector and deposited by the splat
 * policy. With the default unbiased perspective weight, the expectation of every output pixel is the pixel-area
 * average of the line integral of mu through the chosen voxel model (box or tent); the second output holds the
 * per-pixel standard error of that estimate, computed from the same points.
 *
 * \code
 *   using FilterType = itk::PointBasedDRRImageFilter<itk::Image<short, 3>, itk::Image<float, 2>>;
 *   auto drr = FilterType::New();
 *   drr->SetInput(ct);                                 // HU; origin, spacing and direction honoured
 *   drr->GetGeometry()->SetGantryAngleInDegrees(90);   // AP: source anterior
 *   drr->GetGeometry()->SetIsocenter(centre);
 *   drr->SetNumberOfSamples(10000000);
 *   drr->SetSeed(42);
 *   drr->Update();                                     // drr->GetOutput(): line integrals
 * \endcode
 *
 * Reproducibility: a seed gives the same image bit for bit on any number of threads (counter-based random
 * numbers keyed by seed and chunk, integer reduction). Progress events are reported per chunk of samples and
 * AbortGenerateData() stops the render between chunks.
 *
 * Streaming (SetNumberOfStreamDivisions(), SetMemoryBudget()): the volume is read from the pipeline slab by slab and
 * each slab draws its share of the stratified sampler's points, the same points as the render of the whole volume, so
 * the image (with its label or material channels) is the same bit for bit (docs/design.md section 16). Other samplers
 * are not streamed.
 *
 * \sa ExactDRRImageFilter, DRRProjectionGeometry, DRRLevelAliasSampler
 * \ingroup PointBasedDRR
 */
template <typename TInputImage, typename TOutputImage>
class ITK_TEMPLATE_EXPORT PointBasedDRRImageFilter : public DRRImageFilterBase<TInputImage, TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(PointBasedDRRImageFilter);

  /** Standard class type aliases. */
  using Self = PointBasedDRRImageFilter;
  using Superclass = DRRImageFilterBase<TInputImage, TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(PointBasedDRRImageFilter);

  using typename Superclass::OutputImageType;
  /** The sampler policy's base class. */
  using SamplerType = DRRPointSampler;
  /** Box or Tent voxel model. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;
  /** Nearest or Bilinear splat. */
  using SplatEnum = PointBasedDRREnums::Splat;
  /** Unbiased or PaperCount point weighting. */
  using WeightingEnum = PointBasedDRREnums::PointWeighting;

  ///@{
  /** Number of points drawn (N, at least 1; 64-bit). Default DRRPointRenderer::DefaultNumberOfSamples (10^7). */
  itkSetMacro(NumberOfSamples, uint64_t);
  itkGetConstMacro(NumberOfSamples, uint64_t);
  ///@}

  ///@{
  /** The accuracy asked for, a fraction (0.01: 1%) of the estimated relative error
   * (DRRPassCombination::ComputeRelativeError(): the root mean square of the standard-error image over the range of
   * the line-integral image, what NRMSE against the exact pixel-averaged image measures). 0 (the default): render
   * NumberOfSamples points, whatever the error. Above 0: render NumberOfSamples points first, then add independent
   * passes (as Refine() does) of as many points as the estimate says are missing, a tenth more, until the estimate
   * is at most the target; a target that would need more than MaximumNumberOfSamples points in all is refused with
   * an exception. Needs ComputeStandardError. */
  itkSetClampMacro(TargetError, double, 0.0, 1.0);
  itkGetConstMacro(TargetError, double);
  ///@}

  ///@{
  /** The most points a TargetError may spend in all, over its passes (default 2^32). */
  itkSetMacro(MaximumNumberOfSamples, uint64_t);
  itkGetConstMacro(MaximumNumberOfSamples, uint64_t);
  ///@}

  ///@{
  /** Whether the filter chooses its estimator for TargetError (default Off: points as set, refined to the target).
   * On (with a TargetError), each render measures a pilot of the view and renders with the estimator predicted to
   * reach the target with the least CPU work (DRREstimatorChoice): exact rays, k x k per pixel (1 to 16), as
   * ExactDRRImageFilter renders them, whose standard-error output is zero and whose estimated error is the pilot's;
   * plain points; or points with a control variate of factor F (with the box kernel). Points are drawn in the number
   * predicted for the target and then refined to it as without the choice; with ReusePoints the choice of the first
   * pose is kept (see ExpectedNumberOfPoses), a first pose whose estimate misses the target draws its kept points
   * again, more of them, and the poses after it re-project those (GetEstimatedError() says each one's estimate). The
   * settings the choice makes (NumberOfSamples, ControlVariateFactor) are the filter's no longer; the sampler, kernel,
   * splat, seed and strata stay. A streamed render (GetNumberOfSlabs() > 1) renders points: the exact rays need the
   * whole volume. Needs the unbiased weighting and no label channels. */
  itkSetMacro(ChooseEstimator, bool);
  itkGetConstMacro(ChooseEstimator, bool);
  itkBooleanMacro(ChooseEstimator);
  ///@}

  /** Makes the choice of estimator for the current view and TargetError now (ChooseEstimator's pilot), without a
   * render, and returns it: a batch of kept points probes its views with fewer points before it draws them all. */
  const DRREstimatorChoice::Candidate &
  MakeEstimatorChoice();
  /** Makes the choice over several views at once, those whose pilots `pilots` holds (MeasureEstimatorChoice() at
   * each, added up with DRREstimatorChoice::AddViews()), and returns it: a batch's views differ (a lateral view of a
   * chest has more error, and its exact rays cost more, than the AP one), and its estimator is one for all of them.
   * The renders after it keep it as they keep MakeEstimatorChoice()'s (ReusePoints). */
  const DRREstimatorChoice::Candidate &
  MakeEstimatorChoice(const DRREstimatorChoice & pilots);
  /** The pilot of the current view (DRREstimatorChoice::Measure()), without a choice. */
  DRREstimatorChoice
  MeasureEstimatorChoice();

  /** Makes the last choice (MakeEstimatorChoice(), or a render's) the fastest exact rays that reach TargetError, and
   * returns it: for points that stalled above the target (their estimate no longer falls with their number). */
  const DRREstimatorChoice::Candidate &
  FallBackToExactRays()
  {
    return m_Session->FallBackToExactRays(this->MakeRequest());
  }

  /** The pilot of the last choice of estimator (ChooseEstimator), with the candidates' predictions; null before one. */
  const DRREstimatorChoice *
  GetEstimatorChoice() const
  {
    return m_Session->GetEstimatorChoice();
  }
  /** The estimator chosen by the last render with ChooseEstimator. */
  const DRREstimatorChoice::Candidate &
  GetChosenEstimator() const
  {
    return m_Session->GetChosenEstimator();
  }
  /** Every candidate the last choice weighed (ChooseEstimator), with its predicted error and CPU time; empty before
   * one. */
  const std::vector<DRREstimatorChoice::Candidate> &
  GetEstimatorCandidates() const
  {
    return m_Session->GetEstimatorCandidates();
  }

  /** The estimated relative error of the current outputs (see TargetError), 0 before a render. */
  double
  GetEstimatedError() const
  {
    return m_Session->GetEstimatedError();
  }
  /** The part of GetEstimatedError() that is the control variate's coarse image's (its rays' replicates), 0 without
   * one: with ComputeStandardError off its rays are one replicate, not two, and its variance doubles. */
  double
  GetCoarseImageError() const
  {
    return m_Session->GetCoarseImageError();
  }

  ///@{
  /** Seed of the counter-based random streams. Default 0. */
  itkSetMacro(Seed, uint64_t);
  itkGetConstMacro(Seed, uint64_t);
  ///@}

  /** The smallest F `auto` picks for a streamed render: its coarse volume is held whole (4 / F^3 bytes per voxel, 1/32
   * of 16-bit CT at F = 4). */
  static constexpr unsigned int MinimumStreamedAutomaticFactor = DRRPointRenderSession::MinimumStreamedAutomaticFactor;

  ///@{
  /** Voxel model: Box (default, reference Siddon) or Tent (trilinear). */
  itkSetEnumMacro(ReconstructionKernel, KernelEnum);
  itkGetConstMacro(ReconstructionKernel, KernelEnum);
  ///@}

  ///@{
  /** How a point is deposited on the detector: Nearest (default) or Bilinear. */
  itkSetEnumMacro(Splat, SplatEnum);
  itkGetConstMacro(Splat, SplatEnum);
  ///@}

  ///@{
  /** Unbiased (default) or the paper's unweighted count. */
  itkSetEnumMacro(PointWeighting, WeightingEnum);
  itkGetConstMacro(PointWeighting, WeightingEnum);
  ///@}

  ///@{
  /** Number of independent strata R (2 to 256; 0, the default: the sampler's preference, 4 for stratified and 16
   * for metropolis) a sampler of dependent points is run as: its standard error comes from their spread (R - 1
   * degrees of freedom). Fewer strata leave each one more points and so a lower error for stratified sampling, at the
   * price of a noisier standard-error image. 1 is refused at Update() (one stratum of dependent points has no spread
   * to measure). With fewer than 16 points per stratum the render runs as one stratum, whose standard error treats
   * the points as independent, and the filter warns. Samplers of independent points ignore it. */
  void
  SetNumberOfStrata(unsigned int strata)
  {
    strata = std::min(strata, 256u);
    if (m_NumberOfStrata != strata)
    {
      m_NumberOfStrata = strata;
      this->Modified();
    }
  }
  itkGetConstMacro(NumberOfStrata, unsigned int);
  ///@}

  ///@{
  /** The sampler policy. Default: DRRSamplerFactory::DefaultName, DRRStratifiedSampler (systematic along a Morton
   * curve of the mass, culled to the view: the least error for the time, docs/performance.md).
   * \sa DRRSamplerFactory */
  itkSetObjectMacro(Sampler, SamplerType);
  itkGetModifiableObjectMacro(Sampler, SamplerType);
  ///@}

  ///@{
  /** Point reuse (default off). On, the filter keeps the points it draws (DRRPointCloud: 12 to 17 bytes per point,
   * over the whole volume) and, while only the transform, the geometry, the splat or the weighting change, renders
   * by re-projecting them instead of sampling again: registration's many poses of one volume at a fraction of the
   * cost, with frozen noise (the same points at every pose), so that a similarity metric is a smooth function of the
   * pose. A change of input, transfer function, sampler, kernel, number of samples, strata or seed draws new points.
   * Images with reuse equal, bit for bit, those of a fresh filter with reuse at the same pose; they differ from
   * renders without reuse by the single-precision positions of the points and, for culling samplers, by points
   * drawn from the whole volume rather than the view. */
  itkSetMacro(ReusePoints, bool);
  itkGetConstMacro(ReusePoints, bool);
  itkBooleanMacro(ReusePoints);
  ///@}

  ///@{
  /** How many poses the kept points (ReusePoints) are expected to be rendered at (default 1): a batch's number of
   * views. The automatic control variate weighs the coarse image, paid at every pose, against the points, drawn once
   * (DRRControlVariate::ChooseFactor()); without ReusePoints it is ignored. A hint: every pose renders alike. */
  itkSetClampMacro(ExpectedNumberOfPoses, uint64_t, 1, NumericTraits<uint64_t>::max());
  itkGetConstMacro(ExpectedNumberOfPoses, uint64_t);
  ///@}

  /** SetControlVariateFactor() value that lets the filter choose F for the volume and the view at every render
   * (DRRControlVariate::ChooseFactor()). */
  static constexpr unsigned int AutomaticControlVariateFactor = DRRControlVariate::AutomaticFactor;
  /** The largest residual mass M_r / M that AutomaticControlVariateFactor accepts: above it the filter renders without
   * a control variate. At 0.5 the points' error (which scales by about M_r / M) at most halves, which the coarse
   * image's rays do not pay for; on CT M_r / M is 0.07 to 0.2, on a one-slice volume above 1. */
  static constexpr double MaximumAutomaticResidualFraction = DRRPointRenderSession::MaximumAutomaticResidualFraction;

  ///@{
  /** Control variate (DESIGN 10, DRRControlVariate): 0 (default) off; F (2 to DRRControlVariate::MaximumFactor) splits
   * the box model into block means of F^3 voxels, whose image is integrated exactly along 2 ControlVariateRaysPerSide^2
   * jittered rays per pixel, plus the signed residual, which the points sample: the same expectation, with the error
   * of the points scaled by about M_r / M (GetControlVariate()->GetResidualMass() / GetTotalMass()).
   * AutomaticControlVariateFactor: the filter chooses F. Needs the box kernel and the unbiased weighting (Update()
   * throws otherwise). With ReusePoints, the residual's points are kept and the coarse image re-rendered per pose. */
  itkSetMacro(ControlVariateFactor, unsigned int);
  itkGetConstMacro(ControlVariateFactor, unsigned int);
  ///@}
  ///@{
  /** Rays per pixel side k of the control variate's coarse image: two independent replicates of k^2 rays, each
   * jittered in its stratum of the splat's footprint (1 to 16, default 1); their difference gives the coarse image's
   * standard error (DRRExactRayIntegrator::RenderFootprintAverages()). */
  itkSetClampMacro(ControlVariateRaysPerSide, unsigned int, 1, 16);
  itkGetConstMacro(ControlVariateRaysPerSide, unsigned int);
  ///@}

  ///@{
  /** Whether the standard-error output is computed (default On). Off, for renders whose standard error nobody reads (a
   * batch of views): the control variate's coarse image traces one replicate of ray pairs instead of two (half its
   * rays: the same expectation, a little more variance in the coarse part, none in the points'), and the
   * standard-error output is zero. The points and their sums are the same either way. */
  itkSetMacro(ComputeStandardError, bool);
  itkGetConstMacro(ComputeStandardError, bool);
  itkBooleanMacro(ComputeStandardError);
  ///@}
  /** The split of the last render with a control variate (null before one, and after a render without). */
  const DRRControlVariate *
  GetControlVariate() const
  {
    return m_ControlVariateFactor > 0 ? m_Session->GetControlVariate() : nullptr;
  }

  /** The kept points (null unless ReusePoints and after an update); see DRRPointCloud::GetBytesPerPoint(). */
  const DRRPointCloud *
  GetPointCloud() const
  {
    return m_Session->GetPointCloud();
  }

  /** Number of times points were drawn into the kept cloud (each draw after a change that invalidates it). */
  unsigned int
  GetNumberOfPointCloudDraws() const
  {
    return m_Session->GetNumberOfPointCloudDraws();
  }

  /** Per-pixel standard error of the estimate, in the units of the output: for line integrals the estimator's own
   * standard error; for transmission and gray levels carried through the output mode by the delta method. */
  OutputImageType *
  GetStandardErrorOutput()
  {
    return this->GetOutput(1);
  }

  /** Throws if the settings break a rule of the point render: no sampler, no points, one stratum, or a control variate
   * with a kernel or weighting it cannot take or an F out of range (`auto` resolves to off there). Update() checks
   * them first; public, so that a program asks a configured filter before it reads the volume. */
  void
  VerifySettings() const;

  /** Builds the attenuation volume and the sampler's tables now, if the input, transfer function or sampler changed
   * since they were built (Update() does it otherwise): preprocessing once, before many renders. With
   * ChooseEstimator the tables wait for the choice (exact rays need none): the attenuation volume alone. */
  void
  PrepareSampling();

  /** F of a streamed render for the current view: ControlVariateFactor, or for AutomaticControlVariateFactor the
   * view's choice (for ExpectedNumberOfPoses with kept points), at least MinimumStreamedAutomaticFactor (docs/design.md
   * section 16). A caller that must fix `auto`'s choice at one view (pbdrr's batches, at view 0) sets it. */
  unsigned int
  ResolveStreamedControlVariateFactor() const;

  /** Progressive refinement: renders additionalSamples more points as an independent pass (its seed derived from
   * Seed and the pass number) and updates both outputs, through Update(), with the combined estimate: the mean of the
   * passes weighted by the points each drew, and its standard error. Works with every sampler. Throws if nothing was
   * rendered yet, or if anything upstream of the outputs (the filter, its input or attenuation volume, geometry,
   * transform, sampler) changed since (call Update() first). */
  void
  Refine(uint64_t additionalSamples);

  /** Points drawn for the current outputs, as the renderer counts them (NumberOfSamples, or R ceil(N / R) for a
   * sampler of R interleaved strata), over the render and every refinement since. */
  uint64_t
  GetTotalNumberOfSamples() const
  {
    return m_Session->GetPasses().GetNumberOfSamples();
  }

  /** Attenuation mass M of the volume in the room (sum of mu times voxel volume), mm^2, of the last render. */
  double
  GetTotalMass() const
  {
    return m_Session->GetTotalMass();
  }
  /** Number of points that landed on the detector (their nearest pixel inside it), in the last Update() and the
   * refinements since. */
  uint64_t
  GetPointsOnDetector() const
  {
    return m_Session->GetPasses().GetPointsOnDetector();
  }

  /** Includes the sampler's, as well as the geometry's, transform's and transfer function's. */
  ModifiedTimeType
  GetMTime() const override;

  /** An unstreamed point render holds the input, the sampler's tables and the control variate's coarse volume (2.34
   * bytes per voxel on the chest x4 in all, 2.8 on the x2: docs/performance.md): the input pixel and one byte. */
  double
  GetBytesPerVoxel() const override
  {
    return sizeof(typename TInputImage::PixelType) + 1.0;
  }

  /** Streaming draws along the stratified sampler's curve: another sampler cannot stream. */
  std::string
  WhyNotStreamable() const override;

protected:
  PointBasedDRRImageFilter();
  ~PointBasedDRRImageFilter() override = default;

  /** Renders NumberOfSamples points (or re-projects the kept ones), or adds the pass a Refine() asked for, and writes
   * the outputs: the only place they are written. */
  void
  GenerateData() override;
  /** The settings' rules (VerifySettings()), beside the base's. */
  void
  VerifyPreconditions() const override;
  /** Whole brick planes, and whole coarse blocks of the streamed control variate: lcm(8, F). */
  uint64_t
  GetSlabAlignment() const override;
  /** A streamed update of current kept points reads no slab: it re-projects them. */
  bool
  ReadsSlabsAtNextUpdate() const override;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** The session's request: the settings. */
  DRRPointRenderSession::Request
  MakeRequest() const;
  /** The whole volume's slabs, as the session reads them. */
  DRRPointRenderSession::Slabs
  MakeSlabs();
  /** Warns if samples points are too few for the sampler's strata. */
  void
  WarnIfTooFewPerStratum(uint64_t samples) const;
  /** Renders one pass of samples points (the session's next) and adds it to the passes; returns their estimate. */
  DRRPassCombination::Estimate
  RenderPass(const DRRPointRenderSession::Request & request, uint64_t samples);
  /** The chosen points stalled above the target: the exact rays that reach it (DRRPointRenderSession). */
  DRRPassCombination::Estimate
  RenderExactInstead(const DRRPointRenderSession::Request & request);

  /** Whether this render chooses its estimator (ChooseEstimator, a TargetError, the whole volume). */
  bool
  ChoosesTheEstimator() const;
  /** Throws unless the settings are valid and this filter chooses its estimator (ChoosesTheEstimator()). */
  void
  VerifyEstimatorChoice();

  /** Adds passes until the estimated error is at most TargetError (see there). */
  DRRPassCombination::Estimate
  RefineToTarget(const DRRPointRenderSession::Request & request, DRRPassCombination::Estimate estimate);
  /** Warns of a render whose points came near the source; makes one channel the image itself. */
  void
  CompleteResult(DRRPointRenderer::Result & result) const;

  uint64_t                      m_NumberOfSamples{ DRRPointRenderer::DefaultNumberOfSamples };
  uint64_t                      m_Seed{ 0 };
  unsigned int                  m_NumberOfStrata{ 0 };
  KernelEnum                    m_ReconstructionKernel{ KernelEnum::Box };
  SplatEnum                     m_Splat{ SplatEnum::Nearest };
  WeightingEnum                 m_PointWeighting{ WeightingEnum::Unbiased };
  typename SamplerType::Pointer m_Sampler;
  unsigned int                  m_ControlVariateFactor{ 0 };
  unsigned int                  m_ControlVariateRaysPerSide{ 1 };
  bool                          m_ComputeStandardError{ true };
  bool                          m_ReusePoints{ false };
  uint64_t                      m_ExpectedNumberOfPoses{ 1 };
  double                        m_TargetError{ 0.0 };
  uint64_t                      m_MaximumNumberOfSamples{ uint64_t{ 1 } << 32 };
  bool                          m_ChooseEstimator{ false };

  // What the renders are made of (the split, the sampler's tables, the kept points, the passes), and the renders.
  std::unique_ptr<DRRPointRenderSession> m_Session;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkPointBasedDRRImageFilter.hxx"
#endif

#endif
