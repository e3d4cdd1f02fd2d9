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
#ifndef itkPointBasedDRRInterpolateImageFunction_h
#define itkPointBasedDRRInterpolateImageFunction_h

#include "itkDRRCompatibility.h"
#include "itkInterpolateImageFunction.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkTransform.h"

#include <atomic>
#include <mutex>

namespace itk
{
/** \class PointBasedDRRInterpolateImageFunction
 * \brief Drop-in replacement for itk::RayCastInterpolateImageFunction that answers from a point-based DRR.
 *
 * ITK's classic 2D-3D registration (ImageToImageMetric, ResampleImageFilter) asks the interpolator for the line
 * integral through the CT along the ray from the transformed focal point through a transformed detector point, one
 * detector point at a time. This class has the ray caster's interface (SetTransform(), SetFocalPoint(),
 * SetThreshold(), IsInsideBuffer() always true), so that swapping the interpolator's type is the whole change:
 *
 * \code
 *   -using InterpolatorType = itk::RayCastInterpolateImageFunction<CTImageType, double>;
 *   +using InterpolatorType = itk::PointBasedDRRInterpolateImageFunction<CTImageType, double>;
 * \endcode
 *
 * Instead of casting one ray per call, it renders the whole projection once per pose (when the transform's
 * parameters change, detected by its modification time) with a PointBasedDRRImageFilter that keeps its points
 * (ReusePoints: drawn once, re-projected at every pose, frozen noise), and answers each call by bilinear interpolation
 * of that projection at the point where the ray meets the detector. Rendering is guarded by a mutex, so that the
 * multi-threaded callers (ResampleImageFilter, the metrics) can ask concurrently; it runs on its own threads
 * (PlatformMultiThreader), never on the pool of the caller that waits for it.
 *
 * The detector rendered on: by default a virtual one, perpendicular to the line from the focal point to the volume's
 * centre at the first render, behind the volume's bounding sphere, covering the sphere's shadow with a 10% margin at
 * DetectorSize x DetectorSize pixels (rebuilt, with a warning, if the volume moves out of it). For exact agreement
 * with a fixed image, give its grid: SetDetectorFromImage(fixedImage) (the one-slice 3D image of ITK's 2D-3D
 * registration) or SetDetectorGeometry(); calls at its pixel centres then return the filter's pixel values.
 *
 * Values: as the ray caster, the integral along the ray of (input value - Threshold) where the input exceeds the
 * threshold, in input units times mm (with the default AttenuationFromThreshold); set it off to use the filter's own
 * transfer function (HU to mu in 1/mm). The point-based render averages over pixel areas (the box or tent voxel
 * model, GetDRRFilter()->SetReconstructionKernel(); default tent, the ray caster's trilinear model), where the ray
 * caster samples one ray: the two agree to the Monte Carlo noise plus that averaging.
 *
 * The filter that renders is GetDRRFilter(): set its number of samples (default 2 million), seed, sampler (default
 * stratified), splat (default bilinear) there; the transform must be linear (rigid, affine).
 *
 * \sa PointBasedDRRImageFilter, RayCastInterpolateImageFunction
 * \ingroup PointBasedDRR
 */
template <typename TInputImage, typename TCoordinate = double>
class ITK_TEMPLATE_EXPORT PointBasedDRRInterpolateImageFunction
  : public InterpolateImageFunction<TInputImage, TCoordinate>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(PointBasedDRRInterpolateImageFunction);

  /** Standard class type aliases. */
  using Self = PointBasedDRRInterpolateImageFunction;
  using Superclass = InterpolateImageFunction<TInputImage, TCoordinate>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Dimension of the input volume: 3. */
  static constexpr unsigned int InputImageDimension = TInputImage::ImageDimension;
  static_assert(InputImageDimension == 3, "the DRR interpolator takes a 3D volume");

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(PointBasedDRRInterpolateImageFunction);
  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  using typename Superclass::ContinuousIndexType;
  using typename Superclass::IndexType;
  using typename Superclass::InputImageType;
  using typename Superclass::OutputType;
  using typename Superclass::PointType;
  /** Size of the input volume, voxels. */
  using SizeType = typename InputImageType::SizeType;
  /** The room -> CT transform (linear: rigid or affine), as for the ray caster. */
  using TransformType = Transform<TCoordinate, 3, 3>;
  /** A room point, mm. */
  using InputPointType = typename TransformType::InputPointType;
  /** The ray caster's voxel interpolator type (accepted, not used). */
  using InterpolatorType = InterpolateImageFunction<TInputImage, TCoordinate>;
  /** The projection rendered once per pose: line integrals on the detector grid. */
  using ProjectionImageType = Image<float, 2>;
  /** The filter that renders the projection. */
  using FilterType = PointBasedDRRImageFilter<TInputImage, ProjectionImageType>;
  /** The detector geometry rendered on. */
  using GeometryType = DRRProjectionGeometry;

  ///@{
  /** Room -> CT transform, as for the ray caster (shared with the metric or the resampler). Required. */
  itkSetObjectMacro(Transform, TransformType);
  itkGetModifiableObjectMacro(Transform, TransformType);
  ///@}

  ///@{
  /** Accepted for the ray caster's interface; not used (the voxel model is the filter's reconstruction kernel). */
  itkSetObjectMacro(Interpolator, InterpolatorType);
  itkGetModifiableObjectMacro(Interpolator, InterpolatorType);
  ///@}

  ///@{
  /** The focal point (X-ray source) in the room, mm. Default (0, 0, 0). */
  itkSetMacro(FocalPoint, InputPointType);
  itkGetConstMacro(FocalPoint, InputPointType);
  ///@}

  ///@{
  /** Input values at or below the threshold add nothing; above it, value - threshold (input units). Default 0. */
  itkSetMacro(Threshold, double);
  itkGetConstMacro(Threshold, double);
  ///@}

  ///@{
  /** On (default): attenuation = max(0, input - Threshold) per mm, as the ray caster integrates. Off: the DRR
   * filter's transfer function (natural HU -> mu at 60 keV unless set). */
  itkSetMacro(AttenuationFromThreshold, bool);
  itkGetConstMacro(AttenuationFromThreshold, bool);
  itkBooleanMacro(AttenuationFromThreshold);
  ///@}

  ///@{
  /** Pixels per side of the automatic virtual detector, 2 to 8192. Default 256. */
  itkSetClampMacro(DetectorSize, unsigned int, 2, 8192);
  itkGetConstMacro(DetectorSize, unsigned int);
  ///@}

  /** Render on this detector (perspective; the focal point must be its source) instead of the automatic one. */
  void
  SetDetectorGeometry(GeometryType * geometry);

  /** Render on the grid of a one-slice 3D image placed on the detector plane (ITK's 2D-3D registration's fixed
   * image: origin at pixel (0, 0), direction columns along its rows and columns). Uses the current focal point:
   * set it first. */
  void
  SetDetectorFromImage(const ImageBase<3> * image);

  /** The geometry rendered on (null before the first render with the automatic detector). */
  const GeometryType *
  GetDetectorGeometry() const
  {
    return m_Geometry.GetPointer();
  }

  /** The filter that renders: samples, seed, sampler, kernel, splat. Getting it marks this interpolator modified, so
   * that the next call renders with the new settings. */
  FilterType *
  GetDRRFilter()
  {
    this->Modified();
    return m_Filter.GetPointer();
  }

  /** Shares a filter (and so its attenuation volume, sampling tables and kept points) with other interpolators of
   * the same volume: the views of a multi-view registration draw their points once. Renders of interpolators are
   * serialized. */
  void
  SetDRRFilter(FilterType * filter);

  /** The projection of the current pose (renders it if needed). */
  const ProjectionImageType *
  GetProjection() const;

  /** Read-only access to the projection values of the last render (columns fastest). */
  const std::vector<float> &
  GetProjectionValues() const
  {
    this->UpdateProjection();
    return m_Values;
  }

  /** Number of projections rendered so far. */
  uint64_t
  GetNumberOfRenders() const
  {
    return m_NumberOfRenders;
  }

  /** The CT volume; also the input of the DRR filter. */
  void
  SetInputImage(const InputImageType * image) override;

  /** The line integral along the ray from the transformed focal point through point (CT frame, mm): input units times
   * mm with AttenuationFromThreshold, dimensionless (mu in 1/mm times mm) without. */
  OutputType
  Evaluate(const PointType & point) const override;

  /** Evaluate() at the physical point of a continuous index of the CT. */
  OutputType
  EvaluateAtContinuousIndex(const ContinuousIndexType & index) const override;

  ///@{
  /** As the ray caster: every point has a ray. */
  bool
  IsInsideBuffer(const PointType &) const override
  {
    return true;
  }
  bool
  IsInsideBuffer(const ContinuousIndexType &) const override
  {
    return true;
  }
  bool
  IsInsideBuffer(const IndexType &) const override
  {
    return true;
  }
  ///@}

  /** As the ray caster: the size of the whole input volume (a ray reads all of it). Throws without an input. */
  SizeType
  GetRadius() const override;

protected:
  PointBasedDRRInterpolateImageFunction();
  ~PointBasedDRRInterpolateImageFunction() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** Modification time of everything the projection depends on. */
  ModifiedTimeType
  GetRenderTime() const;
  /** Renders the projection for the current pose if it is stale (thread-safe). */
  void
  UpdateProjection() const;
  /** Renders the projection for the current transform and keeps it for Evaluate(). */
  void
  Render() const;
  /** The filter's transfer function: max(0, value - Threshold). */
  void
  SetThresholdTransferFunction() const;
  /** The inverse of the transform's affine map: CT points back to the room. */
  void
  ComputeVolumeToRoom() const;
  /** Builds the automatic detector anew if the volume's bounding sphere moved out of it. */
  void
  FitAutomaticDetector(const InputImageType & input) const;
  /** Keeps the projection and the geometry Evaluate() reads. */
  void
  KeepProjection() const;
  /** The automatic virtual detector for the current pose; true if the current one still covers the volume. */
  bool
  AutomaticDetectorCovers(const PointType & centreInRoom, double radius) const;
  void
  BuildAutomaticDetector(const PointType & centreInRoom, double radius) const;

  typename TransformType::Pointer    m_Transform;
  typename InterpolatorType::Pointer m_Interpolator;
  InputPointType                     m_FocalPoint;
  double                             m_Threshold{ 0.0 };
  bool                               m_AttenuationFromThreshold{ true };
  unsigned int                       m_DetectorSize{ 256 };
  bool                               m_AutomaticDetector{ true };

  typename FilterType::Pointer           m_Filter;
  mutable typename GeometryType::Pointer m_Geometry;
  /** One lock for the renders of every interpolator: they may share a filter. */
  static std::mutex &
                                        GetRenderMutex();
  mutable std::atomic<ModifiedTimeType> m_RenderedTime{ 0 };
  mutable uint64_t                      m_NumberOfRenders{ 0 };
  // What Evaluate() needs, set by Render(): CT -> room (the inverse of the transform's affine map), the detector.
  mutable Matrix<double, 3, 3> m_VolumeToRoomMatrix;
  mutable Vector<double, 3>    m_VolumeToRoomOffset;
  mutable Point<double, 3>     m_Source;
  mutable Vector<double, 3>    m_Normal, m_ColumnStep, m_RowStep; // normal towards the source; u / du, v / dv
  mutable Point<double, 3>     m_Pixel00;
  mutable double               m_SourceToDetectorDistance{ 0.0 };
  mutable int                  m_Columns{ 0 }, m_Rows{ 0 };
  mutable std::vector<float>   m_Values; // the projection, a copy (the filter may be shared)
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkPointBasedDRRInterpolateImageFunction.hxx"
#endif

#endif
