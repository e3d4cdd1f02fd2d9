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
#ifndef itkPointBasedDRRRegistrationMethod_h
#define itkPointBasedDRRRegistrationMethod_h

#include "itkDRRCompatibility.h"
#include "itkDRRProjectionGeometry.h"
#include "itkDataObjectDecorator.h"
#include "itkEuler3DTransform.h"
#include "itkFixedArray.h"
#include "itkImage.h"
#include "itkObjectToObjectOptimizerBase.h"
#include "itkDRRDeadlineMetric.h"
#include "itkPointBasedDRRMetricv4.h"
#include "itkProcessObject.h"

#include <cstdint>
#include <string>
#include <vector>

namespace itk
{
/** \class PointBasedDRRRegistrationMethod
 * \brief Rigid 2D-3D registration: the pose of a CT that makes its DRRs most like one or more real X-rays, composed as
 * ImageRegistrationMethodv4 is, of a metric, an optimizer and a multi-resolution schedule.
 *
 * The pipeline's inputs are the CT (SetVolume(), HU unless the metric's transfer function says otherwise) and the
 * X-rays (AddXRay(): a 2D image, of any intensity, and the DRRProjectionGeometry whose detector grid is the image's;
 * two or more views are registered jointly, which fixes the depth a single view sees only as magnification). Its output
 * is the found pose, as in ITK's ImageRegistrationMethodv4: a decorated transform (GetTransformOutput(),
 * GetTransform()), here an Euler3DTransform from the CT's frame to the room; GetPose() gives it as six numbers.
 *
 * The pose is the CT moved in the room: x -> R (x - c) + c + t, c the centre of the CT's grid, R the rotation of
 * Euler3DTransform's angles (rx, ry, rz) (about z, then x, then y); the identity is where the CT's own frame of
 * reference puts it. As six numbers (PoseType): tx ty tz in mm, rx ry rz in degrees. The metric optimizes its moving
 * transform, the inverse of the pose (room to CT, as the DRR filters and ITK's ray caster take it): by default an
 * Euler3DTransform about the CT's centre; any MatrixOffsetTransformBase set on the metric (VersorRigid3DTransform, ...)
 * is used instead, started at the inverse of the start pose.
 *
 * The parts:
 * - the metric (SetMetric(), default a new PointBasedDRRMetricv4: gradient correlation, stratified kept points,
 *   bilinear splat, analytic derivative). Its settings are the user's (similarity, points, seed, voxel model, transfer
 *   function, exact projector); the method gives it the CT and the X-rays and, per level, the detector shrink factor,
 *   the number of points and the smoothing, then calls its Initialize();
 * - the optimizer (SetOptimizer(): any ITK v4 optimizer; default MakeOptimizer(DefaultOptimizerName), chosen by
 *   benchmark/registration.sh). With SetAutomaticParameterScales() (default on), the method sets the optimizer's
 *   scales at every level from the metric's ComputeParameterScales(): as they are (squared displacements) for the
 *   gradient-descent family, whose steps divide the gradient by them, their square roots (the displacement in mm of one
 *   unit of a parameter) for the others. MakeOptimizer() makes the optimizers tuned here, by name
 *   (GetOptimizerNames(): one list for pbdrr register's help and parsing);
 * - the schedule: one level per shrink factor (SetShrinkFactorsPerLevel(), coarse to fine), with per level the number
 *   of kept points (SetNumberOfSamplesPerLevel(), empty: the metric's own) and the smoothing of DRR and X-ray
 *   (SetSmoothingSigmasPerLevel(), mm at the detector, empty: none). Each level starts where the previous ended. The
 *   defaults (LBFGSB; shrink 4 with 10^6 points smoothed by 5 mm, then shrink 2 with 4 x 10^6 points) were chosen by
 *   benchmark/registration.sh (docs/registration.md);
 * - a global stage (SetNumberOfStarts(), default 1: none): on the first level, the optimizer is run from that many
 *   starts (the start pose, then poses spread over SetStartRadius() mm and degrees about it, deterministic) and the
 *   best end goes on.
 *
 * After each level the method invokes an IterationEvent (GetCurrentLevel(), GetCurrentShrinkFactor(),
 * GetCurrentLevelSimilarity(), GetCurrentLevelEvaluations(), GetCurrentPose() tell about it) and a ProgressEvent. A
 * time limit (SetMaximumTimeInSeconds()) stops the search with the best pose evaluated so far, or the start pose if
 * none was evaluated (GetStoppedByTimeLimit()). Every level keeps the best pose its optimizer evaluated, if it ends
 * elsewhere.
 *
 * The CT must be 3D (a compile-time check); Update() throws ExceptionObject for no X-ray, an X-ray without a geometry,
 * no shrink level or a shrink factor of 0, per-level lists whose length is not the schedule's, a negative time limit,
 * and whatever the metric's Initialize() refuses (an empty or all-air CT, an X-ray that is not finite, constant, of
 * another size than its view, or whose view misses the CT; zero points; a transform that is not linear).
 *
 * \sa PointBasedDRRMetricv4, ImageRegistrationMethodv4, PointBasedDRRImageFilter
 * \ingroup PointBasedDRR
 */
template <typename TInputImage>
class ITK_TEMPLATE_EXPORT PointBasedDRRRegistrationMethod : public ProcessObject
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(PointBasedDRRRegistrationMethod);

  /** Standard class type aliases. */
  using Self = PointBasedDRRRegistrationMethod;
  using Superclass = ProcessObject;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** The CT: a 3D image of HU (or of what the transfer function takes). */
  using InputImageType = TInputImage;
  static_assert(TInputImage::ImageDimension == 3, "PointBasedDRRRegistrationMethod registers a 3D volume");
  /** The metric: a v4 metric of the CT's kept-point DRRs against the X-rays. */
  using MetricType = PointBasedDRRMetricv4<TInputImage>;
  /** Any ITK v4 optimizer. */
  using OptimizerType = ObjectToObjectOptimizerBaseTemplate<double>;
  /** An X-ray, and a DRR at the found pose: a 2D image of float. */
  using XRayImageType = Image<float, 2>;
  /** The field DRR and X-ray both cover: 1 where a pixel counts in the similarity, 0 elsewhere. */
  using MaskImageType = Image<unsigned char, 2>;
  /** The view of an X-ray. */
  using GeometryType = DRRProjectionGeometry;
  /** The pose as a transform from the CT's frame to the room, about the centre of the CT's grid. */
  using TransformType = Euler3DTransform<double>;
  /** The output: the pose's transform, decorated as a data object. */
  using DecoratedTransformType = DataObjectDecorator<TransformType>;
  /** tx ty tz (mm) rx ry rz (degrees). */
  using PoseType = FixedArray<double, 6>;
  /** One shrink factor per level, coarse to fine. */
  using ShrinkFactorsArrayType = std::vector<unsigned int>;
  /** One number of kept points per level. */
  using SamplesArrayType = std::vector<uint64_t>;
  /** One smoothing sigma per level, mm at the detector. */
  using SmoothingSigmasArrayType = std::vector<double>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(PointBasedDRRRegistrationMethod);

  /** The name of the default optimizer (MakeOptimizer()), chosen by benchmark/registration.sh. */
  static constexpr const char * DefaultOptimizerName = "lbfgsb";

  /** The names MakeOptimizer() takes, in the order of pbdrr register's help: "rsgd" (RegularStepGradientDescent),
   * "lbfgsb" (LBFGSB), "cg" (ConjugateGradientLineSearch), "powell" (Powell, derivative-free), "amoeba" (Nelder-Mead,
   * derivative-free). */
  static const std::vector<std::string> &
  GetOptimizerNames();

  /** A new v4 optimizer of that name, tuned for this metric (its settings in the class comment of the .hxx); throws
   * ExceptionObject, listing the names, for another name. */
  static typename OptimizerType::Pointer
  MakeOptimizer(const std::string & name);

  ///@{
  /** The CT to register (the primary input, "Volume"). */
  void
  SetVolume(const InputImageType * volume);
  const InputImageType *
  GetVolume() const;
  ///@}

  /** Adds an X-ray: its 2D image and its view, whose detector size must be the image's size. Its index is
   * GetNumberOfXRays() - 1. The metrics are blind to the image's gain, offset and units, not to its sign: an image
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
  /** The metric (default: a new PointBasedDRRMetricv4). Its CT and X-rays are the method's. */
  itkSetObjectMacro(Metric, MetricType);
  itkGetModifiableObjectMacro(Metric, MetricType);
  ///@}

  ///@{
  /** The optimizer run on every level (default nullptr: MakeOptimizer(DefaultOptimizerName), or "powell" when the
   * metric renders with the exact projector, which has no derivative). */
  itkSetObjectMacro(Optimizer, OptimizerType);
  itkGetModifiableObjectMacro(Optimizer, OptimizerType);
  ///@}

  ///@{
  /** Sets the optimizer's scales at every level from the metric (see the class comment). Default true. */
  itkSetMacro(AutomaticParameterScales, bool);
  itkGetConstMacro(AutomaticParameterScales, bool);
  itkBooleanMacro(AutomaticParameterScales);
  ///@}

  ///@{
  /** The starting pose: tx ty tz (mm) rx ry rz (degrees). Default: the identity (all 0). */
  itkSetMacro(StartPose, PoseType);
  itkGetConstMacro(StartPose, PoseType);
  ///@}

  ///@{
  /** The schedule: one detector binning factor (1 or more) per level, coarse to fine. Default {4, 2} (chosen by
   * benchmark/registration.sh: a level at full resolution cost more time than it bought accuracy). */
  void
  SetShrinkFactorsPerLevel(const ShrinkFactorsArrayType & factors);
  itkGetConstReferenceMacro(ShrinkFactorsPerLevel, ShrinkFactorsArrayType);
  ///@}

  ///@{
  /** Kept points per level (one per shrink factor), or empty: the metric's number on every level. Default {10^6,
   * 4 x 10^6}: the finer level's noise moves the optimum (a magnified view is noisier: a single view's depth drifts
   * towards less magnification), and 4 x 10^6 points keep that drift near 0.3 mm. */
  void
  SetNumberOfSamplesPerLevel(const SamplesArrayType & samples);
  itkGetConstReferenceMacro(NumberOfSamplesPerLevel, SamplesArrayType);
  ///@}

  ///@{
  /** The smoothing of DRR and X-ray per level (one per shrink factor; sigma in mm at the detector, 0: none), or empty:
   * none. Default {5, 0}: the coarse level smoothed (its noise, and its basin, wider), the fine level not. */
  void
  SetSmoothingSigmasPerLevel(const SmoothingSigmasArrayType & sigmas);
  itkGetConstReferenceMacro(SmoothingSigmasPerLevel, SmoothingSigmasArrayType);
  ///@}

  ///@{
  /** The global stage: the number of starts on the first level (1, the default: the start pose alone). */
  itkSetClampMacro(NumberOfStarts, unsigned int, 1, 1000);
  itkGetConstMacro(NumberOfStarts, unsigned int);
  ///@}

  ///@{
  /** How far the global stage's starts spread about the start pose: up to this many mm along each axis and degrees
   * about each axis. Default 10. */
  itkSetMacro(StartRadius, double);
  itkGetConstMacro(StartRadius, double);
  ///@}

  ///@{
  /** The time limit in seconds (wall clock, from the start of Update()'s registration): past it the search stops
   * with the best pose evaluated so far. 0 (the default): no limit. */
  itkSetMacro(MaximumTimeInSeconds, double);
  itkGetConstMacro(MaximumTimeInSeconds, double);
  ///@}

  using Superclass::MakeOutput;
  /** Makes the output, the decorated transform, for index 0. */
  DataObjectPointer
  MakeOutput(DataObjectPointerArraySizeType index) override;

  /** The found pose's transform (from the CT's frame to the room), decorated: the pipeline's output. */
  const DecoratedTransformType *
  GetTransformOutput() const;

  /** The found pose's transform (from the CT's frame to the room). */
  const TransformType *
  GetTransform() const;

  /** The found pose: tx ty tz (mm) rx ry rz (degrees). */
  itkGetConstMacro(Pose, PoseType);

  /** The similarity at the start pose, on the first level (binned). */
  itkGetConstMacro(StartSimilarity, double);

  /** The similarity at the found pose at full resolution, mean over the X-rays. */
  itkGetConstMacro(Similarity, double);

  /** The number of poses at which the DRRs were rendered during the search (each renders every X-ray; a pose with
   * its derivative counts once). */
  itkGetConstMacro(NumberOfEvaluations, SizeValueType);

  /** Of those, the number of poses whose derivative was computed too. */
  itkGetConstMacro(NumberOfDerivativeEvaluations, SizeValueType);

  /** The wall time of the last registration, seconds. */
  itkGetConstMacro(ElapsedSeconds, double);

  /** True if the time limit stopped the last registration. */
  itkGetConstMacro(StoppedByTimeLimit, bool);

  /** The DRR of X-ray index at the found pose, at full resolution (nullptr before Update() or past the last). */
  const XRayImageType *
  GetFinalDRR(unsigned int index) const;

  /** The field DRR and X-ray index both cover at the found pose (1: counted), nullptr before Update() or past the
   * last. */
  const MaskImageType *
  GetFinalMask(unsigned int index) const;

  /** During an IterationEvent: the level just done, 0 for the first. */
  itkGetConstMacro(CurrentLevel, unsigned int);

  /** During an IterationEvent: the shrink factor of the level just done. */
  itkGetConstMacro(CurrentShrinkFactor, unsigned int);

  /** During an IterationEvent: the best similarity found on the level just done (at its binning). */
  itkGetConstMacro(CurrentLevelSimilarity, double);

  /** During an IterationEvent: the poses evaluated on the level just done. */
  itkGetConstMacro(CurrentLevelEvaluations, SizeValueType);

  /** During an IterationEvent: the pose the level just done ended at, tx ty tz (mm) rx ry rz (degrees). */
  itkGetConstMacro(CurrentPose, PoseType);

  /** During an IterationEvent: why the level's optimizer stopped (its GetStopConditionDescription()). */
  itkGetStringMacro(CurrentStopCondition);

  /** The latest of the object's, the X-rays' geometries', the metric's and the optimizer's modification times. */
  ModifiedTimeType
  GetMTime() const override;

  /** The transform of a pose of volume: from the CT's frame to the room, about the centre of volume's grid. */
  static TransformType::Pointer
  MakePoseTransform(const ImageBase<3> * volume, const PoseType & pose);

protected:
  PointBasedDRRRegistrationMethod();
  ~PointBasedDRRRegistrationMethod() override = default;

  /** Throws ExceptionObject for settings the registration cannot use, or no X-ray (see the class comment). */
  void
  VerifyPreconditions() const override;

  /** Registers: the schedule's levels, then the final DRRs, masks and similarity at full resolution. */
  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** The metric as the optimizer sees it: counts the evaluations, keeps the best pose, and stops at the deadline. */
  using DeadlineMetric = DRRDeadlineMetric;

  /** The pose (mm, degrees) as Euler3DTransform's parameters (radians, mm) and back. */
  static TransformType::ParametersType
  ToParameters(const PoseType & pose);
  static PoseType
  ToPose(const TransformType::ParametersType & parameters);

  /** Sets the metric's moving transform to the inverse of pose (the CT's frame to the room). */
  void
  SetMovingTransformToPose(const PoseType & pose) const;
  /** The pose whose inverse the metric's moving transform is. */
  PoseType
  PoseOfMovingTransform() const;

  /** The global stage's k-th start about the start pose (k = 0: the start pose). */
  PoseType
  GlobalStart(unsigned int k) const;

  /** Gives the metric the volume, the X-rays and the start pose (a default Euler3DTransform about the CT's centre). */
  void
  PrepareMetric();
  /** Sets the metric to a level's shrink, points and smoothing; the start similarity at level 0. */
  void
  InitializeLevel(unsigned int level, uint64_t metricSamples);
  /** The optimizer's units per parameter, mm of the points' motion (empty without automatic scales). */
  Array<double>
  ComputeParameterUnits() const;
  /** Searches a level (from several starts on the first), leaves the metric at its best pose and reports it. */
  void
  RegisterLevel(unsigned int                          level,
                OptimizerType *                       optimizer,
                DeadlineMetric &                      watched,
                std::chrono::steady_clock::time_point deadline);
  /** The final DRRs, fields and similarity: full resolution, unsmoothed, the last level's points. */
  void
  MakeFinalImages();

  /** Runs the optimizer on the metric from its transform's parameters; returns the best parameters evaluated. */
  typename MetricType::ParametersType
  Optimize(OptimizerType * optimizer, DeadlineMetric * watched, double & bestValue);

  std::vector<GeometryType::ConstPointer> m_XRayGeometries;
  typename MetricType::Pointer            m_Metric;
  typename OptimizerType::Pointer         m_Optimizer;
  bool                                    m_AutomaticParameterScales{ true };
  PoseType                                m_StartPose{ 0.0 };
  ShrinkFactorsArrayType                  m_ShrinkFactorsPerLevel{ 4, 2 };
  SamplesArrayType                        m_NumberOfSamplesPerLevel{ 1000000, 4000000 };
  SmoothingSigmasArrayType                m_SmoothingSigmasPerLevel{ 5.0, 0.0 };
  unsigned int                            m_NumberOfStarts{ 1 };
  double                                  m_StartRadius{ 10.0 };
  double                                  m_MaximumTimeInSeconds{ 0.0 };

  PoseType                            m_Pose{ 0.0 };
  double                              m_StartSimilarity{ 0.0 };
  double                              m_Similarity{ 0.0 };
  SizeValueType                       m_NumberOfEvaluations{ 0 };
  SizeValueType                       m_NumberOfDerivativeEvaluations{ 0 };
  double                              m_ElapsedSeconds{ 0.0 };
  bool                                m_StoppedByTimeLimit{ false };
  std::vector<XRayImageType::Pointer> m_FinalDRRs;
  std::vector<MaskImageType::Pointer> m_FinalMasks;
  unsigned int                        m_CurrentLevel{ 0 };
  unsigned int                        m_CurrentShrinkFactor{ 0 };
  double                              m_CurrentLevelSimilarity{ 0.0 };
  SizeValueType                       m_CurrentLevelEvaluations{ 0 };
  PoseType                            m_CurrentPose{ 0.0 };
  std::string                         m_CurrentStopCondition;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkPointBasedDRRRegistrationMethod.hxx"
#endif

#endif
