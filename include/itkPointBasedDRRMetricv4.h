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
#ifndef itkPointBasedDRRMetricv4_h
#define itkPointBasedDRRMetricv4_h

#include "itkDRRCompatibility.h"
#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkDRRKeptPointSimilarity.h"
#include "itkDRRPointSampler.h"
#include "itkDRRProjectionGeometry.h"
#include "itkDRRTransferFunction.h"
#include "itkImage.h"
#include "itkObjectToObjectMetricBase.h"
#include "itkOptimizerParameters.h"
#include "itkPointBasedDRREnums.h"
#include "itkTransform.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace itk
{
/** \class PointBasedDRRMetricv4
 * \brief A 2D-3D metric for ITK's v4 optimizers: how unlike a CT's kept-point DRRs are one or more X-rays at a pose,
 * with its analytic derivative.
 *
 * The metric every ITK v4 optimizer takes (LBFGSBOptimizerv4, RegularStepGradientDescentOptimizerv4,
 * ConjugateGradientLineSearchOptimizerv4, QuasiNewtonOptimizerv4, PowellOptimizerv4, OnePlusOneEvolutionaryOptimizerv4,
 * ...). It holds:
 * - the CT (SetVolume(), HU unless SetTransferFunction() says otherwise), or a shared attenuation model
 *   (SetAttenuationVolume(): the output of a DRRImageToAttenuationVolumeFilter, built once for many metrics);
 * - one or more fixed X-rays, each with its view (AddXRay(): a 2D image and a DRRProjectionGeometry, from a geometry
 *   file, a 3 x 4 matrix, RTK's XML or a CT localizer's header), compared at once (biplane and more);
 * - the moving transform (SetMovingTransform()): as PointBasedDRRImageFilter::SetTransform() and ITK's
 *   RayCastInterpolateImageFunction take it, from the room (the X-rays' frame) to the CT's physical frame, any
 *   linear transform (Euler3DTransform, VersorRigid3DTransform, Similarity3DTransform, AffineTransform,
 *   TranslationTransform, a composite of them).
 *   Centre it on the CT (ComputeVolumeCenter()), so that rotations and translations separate. Default: an
 *   Euler3DTransform about the CT's centre, made at Initialize() if none is set;
 * - the similarity (SetSimilarity(): gradient correlation, the default, or normalized cross-correlation,
 *   DRRImageSimilarity) over the field both images cover.
 *
 * The value is minus the mean similarity over the X-rays (minimized, in [-1, 1]), and GetDerivative() follows ITK's v4
 * convention: it returns the negative of the value's derivative with respect to the transform's parameters (the
 * direction v4 optimizers step along), here + d mean S / d theta.
 *
 * The DRRs: N points (SetNumberOfSamples(), drawn once at Initialize() by the sampler, default stratified, with
 * SetSeed()) re-projected at every pose with the bilinear splat: frozen noise, which makes the value a continuous
 * function of the pose and its derivative the exact derivative of what is rendered (almost everywhere: the bilinear
 * splat has kinks at the pixels' centre lines). The derivative costs one backward pass over the same points, which
 * reads the similarity's derivative image at every point's detector position: a value and its derivative cost about
 * two renders per X-ray, whatever the number of parameters (DRRKeptPointSimilarity, DRRPointPoseGradient, the shared
 * design's section 12). There is no control variate here: its coarse image would be traced again at every pose.
 *
 * Multi-resolution: SetDetectorShrinkFactor() bins every detector shrink x shrink (and the X-rays alike, block means),
 * which widens the splat's tent in mm: a smoother metric on coarse levels; SetSmoothingSigma() smooths DRR and X-ray
 * alike by a Gaussian (mm at the detector). The field both cover is fixed at Initialize() at the transform's pose (the
 * pixels whose rays cross the CT's grid): between two Initialize() calls the value is continuous in the pose.
 *
 * Reproducible: the same seed gives the same value and derivative, bit for bit, on any number of threads
 * (SetNumberOfWorkUnits()).
 *
 * Initialize() throws ExceptionObject for: no CT, an empty or all-air CT, no X-ray, an X-ray without a geometry, whose
 * size is not its view's, with a pixel that is not finite, that is constant where it sees the CT, or whose view misses
 * the CT at the pose (no overlap), a transform that is not linear (a B-spline, a displacement field), zero samples, a
 * shrink factor of 0 or a negative smoothing. A pose that moves the CT out of a view gives that view a similarity of 0
 * and a zero derivative: never NaN.
 *
 * \code
 *   auto metric = itk::PointBasedDRRMetricv4<CTImageType>::New();
 *   metric->SetVolume(ct);
 *   metric->AddXRay(xray, geometry);
 *   metric->SetMovingTransform(transform); // e.g. a VersorRigid3DTransform centred on metric->ComputeVolumeCenter()
 *   metric->Initialize();
 *   auto optimizer = itk::LBFGSBOptimizerv4::New();
 *   optimizer->SetMetric(metric);
 *   optimizer->StartOptimization();
 * \endcode
 *
 * \sa PointBasedDRRRegistrationMethod, DRRKeptPointSimilarity, PointBasedDRRImageFilter
 * \ingroup PointBasedDRR
 */
template <typename TVolumeImage>
class ITK_TEMPLATE_EXPORT PointBasedDRRMetricv4 : public ObjectToObjectMetricBaseTemplate<double>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(PointBasedDRRMetricv4);

  /** Standard class type aliases. */
  using Self = PointBasedDRRMetricv4;
  using Superclass = ObjectToObjectMetricBaseTemplate<double>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(PointBasedDRRMetricv4);

  /** The CT: a 3D image of HU (or of what the transfer function takes). */
  using VolumeImageType = TVolumeImage;
  static_assert(TVolumeImage::ImageDimension == 3, "PointBasedDRRMetricv4 compares DRRs of a 3D volume");
  /** An X-ray: a 2D image of float. */
  using XRayImageType = DRRKeptPointSimilarity::XRayImageType;
  /** The field a DRR and an X-ray both cover: 1 where a pixel counts. */
  using MaskImageType = Image<unsigned char, 2>;
  /** The view of an X-ray. */
  using GeometryType = DRRProjectionGeometry;
  /** The moving transform: from the room to the CT's physical frame. */
  using MovingTransformType = Transform<double, 3, 3>;
  /** The shared attenuation model. */
  using AttenuationVolumeType = DRRAttenuationVolume;
  /** The transfer function that makes the model of the CT. */
  using TransferFunctionType = DRRTransferFunction;
  /** NormalizedCorrelation or GradientCorrelation. */
  using SimilarityEnum = PointBasedDRREnums::Similarity;
  /** Box (Siddon) or Tent (trilinear) voxel model. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;
  /** Optimizer parameter scales, one per transform parameter. */
  using ScalesType = OptimizerParameters<double>;
  using typename Superclass::DerivativeType;
  using typename Superclass::MeasureType;
  using typename Superclass::NumberOfParametersType;
  using typename Superclass::ParametersType;
  using typename Superclass::ParametersValueType;

  ///@{
  /** The CT (its model is built at Initialize() by a DRRImageToAttenuationVolumeFilter with the transfer function).
   * Setting it clears a shared model. */
  void
  SetVolume(const VolumeImageType * volume);
  itkGetConstObjectMacro(Volume, VolumeImageType);
  ///@}

  ///@{
  /** A shared attenuation model instead of the CT (kept up to date by Initialize(), which calls its source's
   * Update()). Setting it clears the CT. */
  void
  SetAttenuationVolume(const AttenuationVolumeType * model);
  itkGetConstObjectMacro(AttenuationVolume, AttenuationVolumeType);
  ///@}

  ///@{
  /** The transfer function of the CT's model. Default nullptr: the stage's own (HU, natural, 60 keV). */
  itkSetObjectMacro(TransferFunction, TransferFunctionType);
  itkGetModifiableObjectMacro(TransferFunction, TransferFunctionType);
  ///@}

  /** Adds an X-ray: its 2D image and its view, whose detector size must be the image's size. Its index is
   * GetNumberOfXRays() - 1. The similarities are blind to the image's gain, offset and units, not to its sign: an image
   * that shows attenuation dark (DICOM MONOCHROME1) must be inverted first. */
  void
  AddXRay(const XRayImageType * image, const GeometryType * geometry);

  /** Removes every X-ray. */
  void
  RemoveAllXRays();

  /** The number of X-rays added. */
  unsigned int
  GetNumberOfXRays() const;

  /** The image of X-ray index (nullptr past the last). */
  const XRayImageType *
  GetXRayImage(unsigned int index) const;

  /** The view of X-ray index (nullptr past the last). */
  const GeometryType *
  GetXRayGeometry(unsigned int index) const;

  ///@{
  /** The transform optimized: from the room to the CT's physical frame (see the class comment). */
  itkSetObjectMacro(MovingTransform, MovingTransformType);
  itkGetModifiableObjectMacro(MovingTransform, MovingTransformType);
  ///@}

  ///@{
  /** The similarity: GradientCorrelation (the default) or NormalizedCorrelation. */
  itkSetEnumMacro(Similarity, SimilarityEnum);
  itkGetConstMacro(Similarity, SimilarityEnum);
  ///@}

  ///@{
  /** Kept points, drawn once at Initialize() and re-projected at every pose; a new number draws new points at the next
   * Initialize(). Default 1,000,000. */
  itkSetMacro(NumberOfSamples, uint64_t);
  itkGetConstMacro(NumberOfSamples, uint64_t);
  ///@}

  ///@{
  /** The seed of the kept points. Default 0. */
  itkSetMacro(Seed, uint64_t);
  itkGetConstMacro(Seed, uint64_t);
  ///@}

  ///@{
  /** The voxel model the points are drawn from: Box (default) or Tent. */
  itkSetEnumMacro(ReconstructionKernel, KernelEnum);
  itkGetConstMacro(ReconstructionKernel, KernelEnum);
  ///@}

  ///@{
  /** The sampler that draws the points. Default: a new stratified sampler (DRRSamplerFactory::DefaultName). */
  itkSetObjectMacro(Sampler, DRRPointSampler);
  itkGetModifiableObjectMacro(Sampler, DRRPointSampler);
  ///@}

  ///@{
  /** The detector binning: every X-ray and view binned shrink x shrink (1 or more; a last partial block of pixels is
   * left out). Default 1. */
  itkSetMacro(DetectorShrinkFactor, unsigned int);
  itkGetConstMacro(DetectorShrinkFactor, unsigned int);
  ///@}

  ///@{
  /** A Gaussian smoothing of DRR and X-ray alike, its sigma in mm at the detector (0 or more; default 0: none). */
  itkSetMacro(SmoothingSigma, double);
  itkGetConstMacro(SmoothingSigma, double);
  ///@}

  ///@{
  /** 0 (the default): the kept points. k >= 1: the DRRs of the exact projector of the voxel model instead, k x k rays
   * per pixel (no noise, no points, but no derivative: GetDerivative() throws, for derivative-free optimizers such as
   * PowellOptimizerv4). */
  itkSetMacro(ExactRaysPerPixelSide, unsigned int);
  itkGetConstMacro(ExactRaysPerPixelSide, unsigned int);
  ///@}

  ///@{
  /** The threads an evaluation runs on (1 to ITK_MAX_THREADS). Default: ITK's global default. The same bits on any
   * number. */
  void
  SetNumberOfWorkUnits(ThreadIdType numberOfWorkUnits);
  ThreadIdType
  GetNumberOfWorkUnits() const;
  ///@}

  /** Builds (or updates) the CT's model, makes the default transform if none is set, draws the points if what they are
   * drawn from changed, and bins, smooths and fixes the field of every X-ray at the transform's pose. Call it after
   * changing any setting and before an optimization (PointBasedDRRRegistrationMethod calls it at every level). */
  void
  Initialize() override;

  /** Minus the mean similarity at the moving transform's pose. */
  MeasureType
  GetValue() const override;

  /** The negative of the value's derivative with respect to the moving transform's parameters (v4 convention). */
  void
  GetDerivative(DerivativeType & derivative) const override;

  /** Both, for the price of the derivative (a render and a backward pass per X-ray). */
  void
  GetValueAndDerivative(MeasureType & value, DerivativeType & derivative) const override;

  /** The moving transform's number of parameters. */
  NumberOfParametersType
  GetNumberOfParameters() const override;

  /** The same: the transform has no local support. */
  NumberOfParametersType
  GetNumberOfLocalParameters() const override;

  /** Sets the moving transform's parameters. */
  void
  SetParameters(ParametersType & parameters) override;

  /** The moving transform's parameters. */
  const ParametersType &
  GetParameters() const override;

  /** False: one global transform. */
  bool
  HasLocalSupport() const override;

  /** Adds factor x update to the moving transform's parameters (the transform's own UpdateTransformParameters(): a
   * versor composes). */
  void
  UpdateTransformParameters(const DerivativeType & update, ParametersValueType factor = 1.0) override;

  /** An object metric. */
  MetricCategoryEnum
  GetMetricCategory() const override
  {
    return MetricCategoryEnum::OBJECT_METRIC;
  }

  /** The similarity of X-ray index at the last evaluation (on its binned detector). */
  double
  GetSimilarity(unsigned int index) const;

  /** The DRR of X-ray index at the moving transform's pose, on its binned detector (after Initialize()): line
   * integrals, smoothed as the metric smooths them, origin and spacing of the binned view. */
  typename XRayImageType::Pointer
  ComputeDRR(unsigned int index) const;

  /** The field of X-ray index fixed at Initialize(), on its binned detector (1: counted). */
  typename MaskImageType::Pointer
  GetField(unsigned int index) const;

  /** Parameter scales for a v4 optimizer (SetScales()): for every parameter, the mean squared displacement (mm^2) of
   * the kept points (a few thousand of them; with the exact projector, the attenuating voxels of a subgrid) per unit of
   * the parameter at the current pose, as ITK's RegistrationParameterScalesFromJacobian estimates them over its sample
   * points (1 for a translation in mm, the mean squared lever arm of the CT's attenuation for a rotation in radians).
   * After Initialize(). */
  ScalesType
  ComputeParameterScales() const;

  /** The largest displacement (mm) of those points (the kept points, or the attenuating voxels of a subgrid) for a
   * step of the parameters, to first order: what an optimizer's step does in the room (the scales estimator's
   * EstimateStepScale()). After Initialize(). */
  double
  ComputeMaximumDisplacement(const ParametersType & step) const;

  /** The centre of the CT's grid (the physical point of its central continuous index), mm: where to centre the moving
   * transform. After Initialize() or with a CT set. */
  Point<double, 3>
  ComputeVolumeCenter() const;

  /** The number of evaluations of the value alone since Initialize(). */
  itkGetConstMacro(NumberOfValueEvaluations, SizeValueType);

  /** The number of evaluations of the value with its derivative since Initialize(). */
  itkGetConstMacro(NumberOfDerivativeEvaluations, SizeValueType);

  /** The attenuation model the DRRs are rendered from: the shared one, or the CT's, built at Initialize() (null
   * before). */
  const AttenuationVolumeType *
  GetAttenuationModel() const;

  /** The kept points (null before Initialize()). */
  const DRRPointCloud *
  GetPointCloud() const;

  /** The number of times the points were drawn. */
  unsigned int
  GetNumberOfPointCloudDraws() const;

protected:
  PointBasedDRRMetricv4();
  ~PointBasedDRRMetricv4() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  using StageType = DRRImageToAttenuationVolumeFilter<VolumeImageType>;

  /** For a few thousand points that stand for the CT's attenuation, the 3 x P matrix of their motion in the room per
   * unit of each parameter (-A^-1 dT/dtheta at their room positions). */
  std::vector<vnl_matrix<double>>
  ComputeSampleMotions() const;

  /** Evaluates at the moving transform's pose; derivative may be null. */
  MeasureType
  Evaluate(DerivativeType * derivative) const;

  typename VolumeImageType::ConstPointer       m_Volume;
  typename AttenuationVolumeType::ConstPointer m_AttenuationVolume;
  typename TransferFunctionType::Pointer       m_TransferFunction;
  std::vector<DRRKeptPointSimilarity::XRay>    m_XRays;
  typename MovingTransformType::Pointer        m_MovingTransform;
  SimilarityEnum                               m_Similarity{ SimilarityEnum::GradientCorrelation };
  uint64_t                                     m_NumberOfSamples{ 1000000 };
  uint64_t                                     m_Seed{ 0 };
  KernelEnum                                   m_ReconstructionKernel{ KernelEnum::Box };
  DRRPointSampler::Pointer                     m_Sampler;
  unsigned int                                 m_DetectorShrinkFactor{ 1 };
  double                                       m_SmoothingSigma{ 0.0 };
  unsigned int                                 m_ExactRaysPerPixelSide{ 0 };
  MultiThreaderBase::Pointer                   m_MultiThreader;

  typename StageType::Pointer             m_Stage;
  std::unique_ptr<DRRKeptPointSimilarity> m_Engine;
  mutable std::vector<double>             m_Similarities;
  mutable SizeValueType                   m_NumberOfValueEvaluations{ 0 };
  mutable SizeValueType                   m_NumberOfDerivativeEvaluations{ 0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkPointBasedDRRMetricv4.hxx"
#endif

#endif
