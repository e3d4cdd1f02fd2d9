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
#include "itkDRRPassCombination.h"
#include "itkDRRPointSampler.h"
#include "itkDRRPointRenderer.h"
#include "itkDRRStratifiedSampler.h"
#include "itkDRRStreamedPointRender.h"

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
 * the image is the same bit for bit (docs/design.md section 16). Other samplers and kept points are not streamed.
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
  void
  SetNumberOfSamples(uint64_t samples)
  {
    this->SetSamplingSetting(m_NumberOfSamples, samples);
  }
  itkGetConstMacro(NumberOfSamples, uint64_t);
  ///@}

  ///@{
  /** Seed of the counter-based random streams. Default 0. */
  void
  SetSeed(uint64_t seed)
  {
    this->SetSamplingSetting(m_Seed, seed);
  }
  itkGetConstMacro(Seed, uint64_t);
  ///@}

  /** The smallest F `auto` picks for a streamed render: its coarse volume is held whole (4 / F^3 bytes per voxel, 1/32
   * of 16-bit CT at F = 4). */
  static constexpr unsigned int MinimumStreamedAutomaticFactor = 4;

  ///@{
  /** Voxel model: Box (default, reference Siddon) or Tent (trilinear). */
  void
  SetReconstructionKernel(KernelEnum kernel)
  {
    this->SetSamplingSetting(m_ReconstructionKernel, kernel);
  }
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
    this->SetSamplingSetting(m_NumberOfStrata, std::min(strata, 256u));
  }
  itkGetConstMacro(NumberOfStrata, unsigned int);
  ///@}

  ///@{
  /** The sampler policy. Default: DRRSamplerFactory::DefaultName, DRRStratifiedSampler (systematic along a Morton
   * curve of the mass, culled to the view: the least error for the time, docs/performance.md).
   * \sa DRRSamplerFactory */
  void
  SetSampler(SamplerType * sampler)
  {
    this->SetSamplingSetting(m_Sampler, typename SamplerType::Pointer(sampler));
  }
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
  static constexpr double MaximumAutomaticResidualFraction = 0.5;

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
    return m_ControlVariateFactor > 0 ? m_ControlVariate.GetPointer() : nullptr;
  }

  /** The kept points (null unless ReusePoints and after an update); see DRRPointCloud::GetBytesPerPoint(). */
  const DRRPointCloud *
  GetPointCloud() const
  {
    return m_PointCloud.GetPointer();
  }

  /** Number of times points were drawn into the kept cloud (each draw after a change that invalidates it). */
  itkGetConstMacro(NumberOfPointCloudDraws, unsigned int);

  /** Per-pixel standard error of the estimate, in the units of the output: for line integrals the estimator's own
   * standard error; for transmission and gray levels carried through the output mode by the delta method. */
  OutputImageType *
  GetStandardErrorOutput()
  {
    return this->GetOutput(1);
  }

  /** Builds the attenuation volume and the sampler's tables now, if the input, transfer function or sampler changed
   * since they were built (Update() does it otherwise): preprocessing once, before many renders. */
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
    return m_Passes.GetNumberOfSamples();
  }

  /** Attenuation mass M of the volume in the room (sum of mu times voxel volume), mm^2, of the last render. */
  itkGetConstMacro(TotalMass, double);
  /** Number of points that landed on the detector (their nearest pixel inside it), in the last Update() and the
   * refinements since. */
  uint64_t
  GetPointsOnDetector() const
  {
    return m_Passes.GetPointsOnDetector();
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

protected:
  PointBasedDRRImageFilter();
  ~PointBasedDRRImageFilter() override = default;

  /** Renders NumberOfSamples points (or re-projects the kept ones), or adds the pass a Refine() asked for, and writes
   * the outputs: the only place they are written. */
  void
  GenerateData() override;

  /** Renders one pass of samples points with the seed of pass number `pass`. */
  DRRPointRenderer::Result
  RenderPass(uint64_t samples, unsigned int pass);

  /** Renders the kept points for the current pose with the settings of pass 0, drawing them first if they are missing
   * or stale. */
  DRRPointRenderer::Result
  RenderKeptPoints(DRRPointRenderer::Settings settings);

  /** The settings' rules (at least one sample, strata, the control variate's kernel, weighting and factor), in one
   * place: before every render, at Update() (ITK calls VerifyPreconditions() before GenerateData()), PrepareSampling()
   * and Refine() (with its own number of samples). Throws an ExceptionObject naming the rule. */
  void
  VerifySettings(uint64_t samples) const;

  /** Settings of pass number `pass` (its seed derived from Seed and the pass); VerifySettings() has passed. */
  DRRPointRenderer::Settings
  MakeSettings(uint64_t samples, unsigned int pass) const;

  /** Makes the control variate for the current attenuation volume and factor, unless the one made is still
   * current (neither the volume nor the factor changed since it was made); frees it for no control variate. */
  void
  PrepareControlVariate();
  /** The volume the sampler draws from: the attenuation volume, or the control variate's residual. */
  const DRRAttenuationVolume &
  GetSamplingVolume() const;
  /** Initializes the sampler on volume unless its tables are newer than the volume, the sampler's settings and the
   * last SetSampler(). */
  void
  InitializeSampler(const DRRAttenuationVolume & volume);

  /** F of the next render: ControlVariateFactor, or the choice for the view (AutomaticControlVariateFactor). */
  unsigned int
  ResolveControlVariateFactor();

  /** Adds the control variate's coarse image for the current pose to a render of the residual (no-op without one). */
  void
  AddControlVariateImage(const DRRPointRenderer::Settings & settings, DRRPointRenderer::Result & result);
  /** Adds the coarse image of a control variate (the filter's, or a streamed render's) for projection, with the
   * settings' splat and seed, the filter's rays per side and one replicate unless a standard error is computed. */
  void
  AddCoarseImage(const DRRControlVariate &          controlVariate,
                 const DRRPointProjection &         projection,
                 const DRRPointRenderer::Settings & settings,
                 DRRPointRenderer::Result &         result);
  /** The base's checks (the input is set), then VerifySettings() with the number of samples of the coming pass. */
  void
  VerifyPreconditions() const override;
  /** The base's reasons, and the point-based filter's: a sampler other than the stratified one (its tables are the
   * whole volume's). */
  std::string
  WhyNotStreamable() const override;

  /** Streamed slabs start at whole brick planes (8, the stratified sampler's bricks) and whole coarse blocks of the
   * control variate (F planes). */
  uint64_t
  GetSlabAlignment() const override;
  /** One pass of a render streamed by slabs (docs/design.md section 16): a first pass over the slabs gathers the
   * masses along the sampler's curve (and the coarse volume), a second draws each slab's window of the samples into
   * the whole render's sums, or, keepPoints, into kept points of the whole volume (m_PointCloud, with the coarse volume
   * m_StreamedControlVariate; the result is then empty). The same image, bit for bit, as the render of the whole
   * volume. */
  DRRPointRenderer::Result
  RenderStreamed(const DRRPointRenderer::Settings & settings, bool keepPoints);
  /** Renders the kept points for the current pose, drawing them first slab by slab (RenderStreamed() keeping the
   * points of the whole volume, and the control variate's coarse volume) if they are missing or stale: each slab is
   * read for the first view only, every later pose re-projects the points. */
  DRRPointRenderer::Result
  RenderStreamedKeptPoints(const DRRPointRenderer::Settings & settings);
  /** True if kept points drawn slab by slab are current: nothing they are made of (sampling settings, sampler,
   * transfer function, anything upstream of the input) is newer. */
  bool
  StreamedPointCloudIsCurrent() const;
  /** A streamed update of current kept points reads no slab: it re-projects them. */
  bool
  ReadsSlabsAtNextUpdate() const override;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** Sets a setting the drawn points depend on: marks the filter, and the sampling settings, modified if new. */
  template <typename TValue>
  void
  SetSamplingSetting(TValue & member, const TValue & value)
  {
    if (member != value)
    {
      member = value;
      m_SamplingSettingsTime.Modified();
      this->Modified();
    }
  }
  // The settings.
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

  // What the renders are made of, each stale once something it was made from is newer: the attenuation volume ->
  // the control variate -> the sampler's tables -> the kept points.
  TimeStamp                          m_SamplingSettingsTime; // the last change of a setting the points depend on
  DRRAttenuationVolume::ConstPointer m_PreparedVolume;       // the attenuation volume the control variate is of
  DRRControlVariate::Pointer         m_ControlVariate;       // null: none (off, declined or not made yet)
  TimeStamp                          m_ControlVariateTime;   // when it was made, or declined
  unsigned int                       m_PreparedFactor{ 0 };  // its F, or F declined (`auto` found M_r / M too large)
  TimeStamp                          m_SamplerTime;          // when the sampler was initialized
  DRRPointCloud::Pointer             m_PointCloud;
  DRRControlVariate::Pointer         m_StreamedControlVariate;      // the coarse volume of kept points drawn streamed
  bool                               m_PointCloudStreamed{ false }; // the kept points were drawn slab by slab
  TimeStamp                          m_PointCloudTime;              // when the kept points were drawn
  unsigned int                       m_NumberOfPointCloudDraws{ 0 };
  // The renders of the kept points reuse their sums from pose to pose.
  std::shared_ptr<DRRPointRenderer::Workspace> m_PointCloudWorkspace;

  // The outputs: the passes of the last render and the refinements since, and what a Refine() asks for.
  DRRPassCombination m_Passes;
  double             m_TotalMass{ 0.0 };
  TimeStamp          m_RenderTime;             // when the outputs were last written
  uint64_t           m_RefinementSamples{ 0 }; // the points of the pass Refine() asked for (0: a render)
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkPointBasedDRRImageFilter.hxx"
#endif

#endif
