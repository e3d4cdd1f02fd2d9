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
#include "itkDRRTransferFunction.h"
#include "itkDataObjectDecorator.h"
#include "itkEuler3DTransform.h"
#include "itkFixedArray.h"
#include "itkImage.h"
#include "itkPointBasedDRREnums.h"
#include "itkProcessObject.h"

#include <cstdint>
#include <string>
#include <vector>

namespace itk
{
/** \class PointBasedDRRRegistrationMethod
 * \brief Rigid 2D-3D registration: the pose of a CT that makes its DRRs most like one or more real X-rays.
 *
 * The pipeline's inputs are the CT (SetVolume(), HU unless a transfer function says otherwise) and the X-rays
 * (AddXRay(): a 2D image, of any intensity, and the DRRProjectionGeometry whose detector grid is the image's). Its
 * output is the found pose, as in ITK's ImageRegistrationMethodv4: a decorated transform (GetTransformOutput(),
 * GetTransform()), here an Euler3DTransform from the CT's frame to the room. GetPose() gives it as six numbers,
 * GetSimilarity(), GetNumberOfEvaluations() and GetFinalDRR() / GetFinalMask() what it was found with.
 *
 * The pose is the CT moved in the room: x -> R (x - c) + c + t, c the centre of the CT's grid, R the rotation of
 * Euler3DTransform's angles (rx, ry, rz) (about z, then x, then y); the identity is where the CT's own frame of
 * reference puts it. As six numbers (PoseType): tx ty tz in mm, rx ry rz in degrees.
 *
 * The similarity (SetMetric(), DRRImageSimilarity) is the gradient correlation ("gc", the default) or the normalized
 * cross-correlation ("ncc") of DRR and X-ray over the pixels whose rays cross the CT's grid at the pose (the field
 * both cover), averaged over the X-rays. Powell's method (PowellOptimizer, derivative-free; one unit is one degree or
 * one mm) maximizes it on each level of a multi-resolution schedule (SetShrinkFactorsPerLevel(): the detector binned
 * shrink x shrink, the X-ray block-averaged alike), each level starting where the previous one ended.
 *
 * The DRRs: PointBasedDRRImageFilter with kept points (SetReusePoints(): the points are drawn once per X-ray and
 * re-projected at every pose and level; bilinear splat, so that the cost is continuous in the pose: frozen noise,
 * the shared design, section 9), or ExactDRRImageFilter (SetUseExactProjector(), k x k rays per pixel).
 *
 * After each level the method invokes an IterationEvent (GetCurrentLevel(), GetCurrentShrinkFactor(),
 * GetCurrentLevelSimilarity(), GetCurrentLevelEvaluations(), GetCurrentPose() tell about it) and a ProgressEvent. A
 * time limit (SetMaximumTimeInSeconds()) stops the search with the best pose evaluated so far
 * (GetStoppedByTimeLimit()).
 *
 * The CT must be 3D (a compile-time check); Update() throws ExceptionObject for an empty CT, no X-ray, an X-ray
 * without a geometry or whose size is not its detector's, an invalid geometry, no shrink level or a shrink factor of
 * 0, an unknown metric, 0 samples (kept points) or a negative time limit.
 *
 * \sa DRRImageSimilarity, PointBasedDRRImageFilter, ExactDRRImageFilter, DRRProjectionGeometry
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
  /** The transfer function of the DRR filters. */
  using TransferFunctionType = DRRTransferFunction;
  /** Box (Siddon) or Tent (trilinear) voxel model. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(PointBasedDRRRegistrationMethod);

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
  /** The starting pose: tx ty tz (mm) rx ry rz (degrees). Default: the identity (all 0). */
  itkSetMacro(StartPose, PoseType);
  itkGetConstMacro(StartPose, PoseType);
  ///@}

  ///@{
  /** The schedule: one detector binning factor (1 or more) per level, coarse to fine. Default {2, 1}: the last level
   * at full resolution, where the gradients decide the rotations out of the view's plane. */
  void
  SetShrinkFactorsPerLevel(const ShrinkFactorsArrayType & factors);
  itkGetConstReferenceMacro(ShrinkFactorsPerLevel, ShrinkFactorsArrayType);
  ///@}

  ///@{
  /** The similarity: "gc" (gradient correlation, the default) or "ncc" (DRRImageSimilarity::GetMetricNames()). */
  itkSetStringMacro(Metric);
  itkGetStringMacro(Metric);
  ///@}

  ///@{
  /** Renders the DRRs with ExactDRRImageFilter (no noise, slower per DRR) instead of kept points. Default false. */
  itkSetMacro(UseExactProjector, bool);
  itkGetConstMacro(UseExactProjector, bool);
  itkBooleanMacro(UseExactProjector);
  ///@}

  ///@{
  /** The exact projector's rays per pixel side k: a pixel is the average of k x k rays, as a detector pixel
   * integrates (one ray samples a point: on sharp edges the NCC optimum moves by tenths of a degree). 1 to 1024,
   * default 2. */
  itkSetClampMacro(ExactRaysPerPixelSide, unsigned int, 1, 1024);
  itkGetConstMacro(ExactRaysPerPixelSide, unsigned int);
  ///@}

  ///@{
  /** Kept points per X-ray, drawn once and re-projected at every pose. Default 4,000,000. */
  itkSetMacro(NumberOfSamples, uint64_t);
  itkGetConstMacro(NumberOfSamples, uint64_t);
  ///@}

  ///@{
  /** The seed of the kept points: X-ray k draws with Seed + k. Default 0: the same seed, the same pose on any
   * number of threads. */
  itkSetMacro(Seed, uint64_t);
  itkGetConstMacro(Seed, uint64_t);
  ///@}

  ///@{
  /** The time limit in seconds (wall clock, from the start of Update()'s registration): past it the search stops
   * with the best pose evaluated so far. 0 (the default): no limit. */
  itkSetMacro(MaximumTimeInSeconds, double);
  itkGetConstMacro(MaximumTimeInSeconds, double);
  ///@}

  ///@{
  /** The transfer function every DRR filter uses (shared). Default nullptr: the filters' own (HU, natural). */
  itkSetObjectMacro(TransferFunction, TransferFunctionType);
  itkGetModifiableObjectMacro(TransferFunction, TransferFunctionType);
  ///@}

  ///@{
  /** The voxel model of the DRRs: Box (default) or Tent. */
  itkSetEnumMacro(ReconstructionKernel, KernelEnum);
  itkGetConstMacro(ReconstructionKernel, KernelEnum);
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

  /** The number of poses at which the DRRs were rendered during the search (each renders every X-ray). */
  itkGetConstMacro(NumberOfEvaluations, SizeValueType);

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

  /** The latest of the object's, the X-rays' geometries' and the transfer function's modification times. */
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

  /** Throws ExceptionObject for an empty volume, an invalid view or an X-ray whose size is not its view's. */
  void
  VerifyInputInformation() const override;

  /** Registers: the schedule's levels, then the final DRRs, masks and similarity at full resolution. */
  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** The cost Powell's method minimizes on one level: 1 - the mean similarity of the X-rays and the DRRs. */
  class LevelCost;
  /** Thrown by the cost when the time limit has passed: the best pose so far is the answer. */
  struct TimeIsUp
  {};

  /** A copy of a view, bit for bit. */
  static GeometryType::Pointer
  CopyGeometry(const GeometryType * geometry);
  /** The view binned shrink x shrink (a last partial block of pixels is left out). */
  static GeometryType::Pointer
  BinnedGeometry(const GeometryType * geometry, unsigned int shrink);
  /** The image binned as BinnedGeometry() bins its view: block means. */
  static std::vector<float>
  BinnedImage(const XRayImageType * image, unsigned int shrink);
  /** The pixels whose rays cross the volume's grid at the pose: the field DRR and X-ray both cover. */
  static std::vector<uint8_t>
  CoveredField(const GeometryType * geometry, const ImageBase<3> * volume, const TransformType * pose);

  /** The pose (mm, degrees) as Euler3DTransform's parameters (radians, mm) and back. */
  static TransformType::ParametersType
  ToParameters(const PoseType & pose);
  static PoseType
  ToPose(const TransformType::ParametersType & parameters);

  std::vector<GeometryType::ConstPointer> m_XRayGeometries;
  PoseType                                m_StartPose{ 0.0 };
  ShrinkFactorsArrayType                  m_ShrinkFactorsPerLevel{ 2, 1 };
  std::string                             m_Metric{ "gc" };
  bool                                    m_UseExactProjector{ false };
  unsigned int                            m_ExactRaysPerPixelSide{ 2 };
  uint64_t                                m_NumberOfSamples{ 4000000 };
  uint64_t                                m_Seed{ 0 };
  double                                  m_MaximumTimeInSeconds{ 0.0 };
  typename TransferFunctionType::Pointer  m_TransferFunction;
  KernelEnum                              m_ReconstructionKernel{ KernelEnum::Box };

  PoseType                            m_Pose{ 0.0 };
  double                              m_StartSimilarity{ 0.0 };
  double                              m_Similarity{ 0.0 };
  SizeValueType                       m_NumberOfEvaluations{ 0 };
  double                              m_ElapsedSeconds{ 0.0 };
  bool                                m_StoppedByTimeLimit{ false };
  std::vector<XRayImageType::Pointer> m_FinalDRRs;
  std::vector<MaskImageType::Pointer> m_FinalMasks;
  unsigned int                        m_CurrentLevel{ 0 };
  unsigned int                        m_CurrentShrinkFactor{ 0 };
  double                              m_CurrentLevelSimilarity{ 0.0 };
  SizeValueType                       m_CurrentLevelEvaluations{ 0 };
  PoseType                            m_CurrentPose{ 0.0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkPointBasedDRRRegistrationMethod.hxx"
#endif

#endif
