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
#ifndef itkPointBasedDRRInterpolateImageFunction_hxx
#define itkPointBasedDRRInterpolateImageFunction_hxx

#include "itkPointBasedDRRInterpolateImageFunction.h"
#include "itkDRRStratifiedSampler.h"
#include "itkPlatformMultiThreader.h"

#include <cmath>

namespace itk
{
template <typename TInputImage, typename TCoordinate>
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::PointBasedDRRInterpolateImageFunction()
  : m_Filter(FilterType::New())
{
  static_assert(std::is_same<TCoordinate, double>::value, "the DRR filter takes a Transform<double, 3, 3>");
  m_FocalPoint.Fill(0.0);
  m_Filter->SetReusePoints(true);
  m_Filter->SetSampler(DRRStratifiedSampler::New());
  m_Filter->SetSplat(PointBasedDRREnums::Splat::Bilinear);
  m_Filter->SetReconstructionKernel(PointBasedDRREnums::ReconstructionKernel::Tent);
  m_Filter->SetNumberOfSamples(DRRPointRenderer::DefaultNumberOfSamples / 5); // a registration's many views
  // The render runs from inside the callers' worker threads (a multi-threaded resampler or metric): on threads of its
  // own, a pool's threads never wait for work queued behind themselves.
  m_Filter->SetMultiThreader(PlatformMultiThreader::New());
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::SetInputImage(const InputImageType * image)
{
  Superclass::SetInputImage(image);
  const std::lock_guard<std::mutex> lock(GetRenderMutex());
  m_Filter->SetInput(image);
  this->Modified();
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::SetDRRFilter(FilterType * filter)
{
  if (!filter)
  {
    itkExceptionMacro("SetDRRFilter: null filter");
  }
  const std::lock_guard<std::mutex> lock(GetRenderMutex());
  m_Filter = filter;
  if (this->GetInputImage())
  {
    m_Filter->SetInput(this->GetInputImage());
  }
  this->Modified();
}

template <typename TInputImage, typename TCoordinate>
std::mutex &
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::GetRenderMutex()
{
  static std::mutex mutex;
  return mutex;
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::SetDetectorGeometry(GeometryType * geometry)
{
  m_Geometry = geometry;
  m_AutomaticDetector = geometry == nullptr;
  this->Modified();
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::SetDetectorFromImage(const ImageBase<3> * image)
{
  if (!image)
  {
    itkExceptionMacro("SetDetectorFromImage: no image");
  }
  const auto size = image->GetLargestPossibleRegion().GetSize();
  if (size[2] != 1)
  {
    itkExceptionMacro("SetDetectorFromImage: the detector image must have one slice, not " << size[2]);
  }
  using VectorType = DRRProjectionGeometry::VectorType;
  using PointType3 = DRRProjectionGeometry::PointType;
  VectorType u, v;
  for (unsigned int r = 0; r < 3; ++r)
  {
    u[r] = image->GetDirection()[r][0];
    v[r] = image->GetDirection()[r][1];
  }
  const double du = image->GetSpacing()[0];
  const double dv = image->GetSpacing()[1];
  PointType3   centre = image->GetOrigin();
  centre += u * (du * (size[0] - 1.0) / 2.0) + v * (dv * (size[1] - 1.0) / 2.0);
  PointType3 source;
  for (unsigned int r = 0; r < 3; ++r)
  {
    source[r] = m_FocalPoint[r];
  }
  auto geometry = GeometryType::New();
  try
  {
    geometry->SetExplicitPerspectiveGeometry(source, centre, u, v);
  }
  catch (const ExceptionObject &)
  {
    // The focal point is on the other side of the image's plane for this handedness: the same pixel centres, with
    // the columns counted the other way.
    geometry->SetExplicitPerspectiveGeometry(source, centre, -u, v);
  }
  geometry->SetDetectorSize({ { static_cast<unsigned int>(size[0]), static_cast<unsigned int>(size[1]) } });
  DRRProjectionGeometry::DetectorVectorType spacing;
  spacing[0] = du;
  spacing[1] = dv;
  geometry->SetDetectorSpacing(spacing);
  geometry->VerifyGeometry();
  this->SetDetectorGeometry(geometry);
}

template <typename TInputImage, typename TCoordinate>
auto
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::GetRadius() const -> SizeType
{
  const InputImageType * input = this->GetInputImage();
  if (!input)
  {
    itkExceptionMacro("Input image required!");
  }
  return input->GetLargestPossibleRegion().GetSize();
}

template <typename TInputImage, typename TCoordinate>
ModifiedTimeType
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::GetRenderTime() const
{
  // Only what callers change between evaluations: the filter's settings reach it through GetDRRFilter(), which
  // marks this object modified; what Render() changes on the filter is not looked at here, so that other threads may
  // check without the lock while one renders.
  ModifiedTimeType latest = this->GetMTime();
  if (m_Transform)
  {
    latest = std::max(latest, m_Transform->GetMTime());
  }
  if (this->GetInputImage())
  {
    latest = std::max(latest, this->GetInputImage()->GetMTime());
  }
  return latest;
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::UpdateProjection() const
{
  const ModifiedTimeType wanted = this->GetRenderTime();
  if (wanted == m_RenderedTime.load(std::memory_order_acquire))
  {
    return;
  }
  const std::lock_guard<std::mutex> lock(GetRenderMutex());
  if (wanted == m_RenderedTime.load(std::memory_order_relaxed))
  {
    return; // another thread rendered it while this one waited
  }
  this->Render();
  m_RenderedTime.store(wanted, std::memory_order_release);
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::Render() const
{
  const InputImageType * input = this->GetInputImage();
  if (!input)
  {
    itkExceptionMacro("no input image: SetInputImage() first");
  }
  if (!m_Transform)
  {
    itkExceptionMacro("no transform: SetTransform() first (as for RayCastInterpolateImageFunction)");
  }
  if (m_AttenuationFromThreshold)
  {
    this->SetThresholdTransferFunction();
  }
  m_Filter->SetTransform(m_Transform);
  this->ComputeVolumeToRoom();
  if (m_AutomaticDetector)
  {
    this->FitAutomaticDetector(*input);
  }
  else if (!m_Geometry)
  {
    itkExceptionMacro("no detector geometry");
  }
  m_Filter->SetGeometry(m_Geometry);
  m_Filter->Update();
  ++m_NumberOfRenders;
  this->KeepProjection();
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::SetThresholdTransferFunction() const
{
  // max(0, value - threshold): zero up to the threshold, slope 1 far beyond any CT value.
  constexpr double                         span = 1e9;
  const DRRTransferFunction::PointListType points{ { m_Threshold, 0.0 }, { m_Threshold + span, span } };
  DRRTransferFunction *                    transfer = m_Filter->GetTransferFunction();
  if (transfer->GetMode() != PointBasedDRREnums::TransferFunction::PiecewiseLinear ||
      transfer->GetPiecewiseLinearPoints() != points)
  {
    transfer->SetPiecewiseLinearPoints(points);
  }
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::ComputeVolumeToRoom() const
{
  // The transform's affine map room -> CT, inverted: Evaluate() takes CT points back to the room.
  InputPointType zero;
  zero.Fill(0.0);
  const auto           image0 = m_Transform->TransformPoint(zero);
  Matrix<double, 3, 3> roomToVolume;
  for (unsigned int c = 0; c < 3; ++c)
  {
    InputPointType unit = zero;
    unit[c] = 1.0;
    const auto imageC = m_Transform->TransformPoint(unit);
    for (unsigned int r = 0; r < 3; ++r)
    {
      roomToVolume[r][c] = imageC[r] - image0[r];
    }
  }
  m_VolumeToRoomMatrix = Matrix<double, 3, 3>(roomToVolume.GetInverse());
  for (unsigned int r = 0; r < 3; ++r)
  {
    m_VolumeToRoomOffset[r] = -(m_VolumeToRoomMatrix[r][0] * image0[0] + m_VolumeToRoomMatrix[r][1] * image0[1] +
                                m_VolumeToRoomMatrix[r][2] * image0[2]);
  }
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::FitAutomaticDetector(
  const InputImageType & input) const
{
  // The volume's bounding sphere (voxel boxes included), in the room.
  const auto                 region = input.GetLargestPossibleRegion();
  ContinuousIndex<double, 3> centreIndex;
  Vector<double, 3>          halfDiagonal;
  for (unsigned int a = 0; a < 3; ++a)
  {
    centreIndex[a] = region.GetIndex()[a] + (region.GetSize()[a] - 1.0) / 2.0;
  }
  PointType centre;
  input.TransformContinuousIndexToPhysicalPoint(centreIndex, centre);
  for (unsigned int r = 0; r < 3; ++r)
  {
    halfDiagonal[r] = 0.0;
    for (unsigned int a = 0; a < 3; ++a)
    {
      halfDiagonal[r] += std::abs(input.GetDirection()[r][a]) * input.GetSpacing()[a] * region.GetSize()[a] / 2.0;
    }
  }
  // Lengths in the room: at most the largest stretch of CT -> room (1 for a rigid transform).
  double radius = halfDiagonal.GetNorm() * m_VolumeToRoomMatrix.GetVnlMatrix().frobenius_norm() / std::sqrt(3.0);
  radius = std::max(radius, halfDiagonal.GetNorm());
  PointType centreInRoom;
  for (unsigned int r = 0; r < 3; ++r)
  {
    centreInRoom[r] = m_VolumeToRoomOffset[r] + m_VolumeToRoomMatrix[r][0] * centre[0] +
                      m_VolumeToRoomMatrix[r][1] * centre[1] + m_VolumeToRoomMatrix[r][2] * centre[2];
  }
  if (!this->AutomaticDetectorCovers(centreInRoom, radius))
  {
    if (m_Geometry)
    {
      itkWarningMacro("the volume moved out of the virtual detector: it is rebuilt for the current pose, which "
                      "changes the projection's pixel grid");
    }
    this->BuildAutomaticDetector(centreInRoom, radius);
  }
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::KeepProjection() const
{
  m_Geometry->VerifyGeometry();
  m_Source = m_Geometry->GetSourcePosition();
  m_Normal = m_Geometry->GetNormal();
  m_ColumnStep = m_Geometry->GetColumnDirection() / m_Geometry->GetDetectorSpacing()[0];
  m_RowStep = m_Geometry->GetRowDirection() / m_Geometry->GetDetectorSpacing()[1];
  m_Pixel00 = m_Geometry->GetPixelCenter(0.0, 0.0);
  m_SourceToDetectorDistance = m_Geometry->GetSourceToDetectorDistance();
  m_Columns = static_cast<int>(m_Geometry->GetDetectorSize()[0]);
  m_Rows = static_cast<int>(m_Geometry->GetDetectorSize()[1]);
  const ProjectionImageType * projection = m_Filter->GetOutput();
  m_Values.assign(projection->GetBufferPointer(),
                  projection->GetBufferPointer() + projection->GetBufferedRegion().GetNumberOfPixels());
}

template <typename TInputImage, typename TCoordinate>
bool
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::AutomaticDetectorCovers(const PointType & centreInRoom,
                                                                                         double            radius) const
{
  if (!m_Geometry)
  {
    return false;
  }
  Vector<double, 3> toCentre;
  for (unsigned int r = 0; r < 3; ++r)
  {
    toCentre[r] = centreInRoom[r] - m_FocalPoint[r];
  }
  const double distance = toCentre.GetNorm();
  if (!(distance > radius))
  {
    return false; // BuildAutomaticDetector() says why
  }
  // The sphere's shadow is a cone of half-angle asin(R / D) about the direction to its centre; it must fit in the
  // detector's cone (the square's inscribed circle), and the detector plane must stay behind the sphere.
  const double offAxis = std::acos(std::min(1.0, -(toCentre * m_Geometry->GetNormal()) / distance));
  const double halfWidth = 0.5 * m_Geometry->GetDetectorSize()[0] * m_Geometry->GetDetectorSpacing()[0];
  const double detectorHalfAngle = std::atan(halfWidth / m_Geometry->GetSourceToDetectorDistance());
  const double depth = -(toCentre * m_Geometry->GetNormal());
  return offAxis + std::asin(radius / distance) <= detectorHalfAngle &&
         depth + radius <= m_Geometry->GetSourceToDetectorDistance();
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::BuildAutomaticDetector(const PointType & centreInRoom,
                                                                                        double            radius) const
{
  DRRProjectionGeometry::VectorType towardsSource;
  DRRProjectionGeometry::PointType  isocenter;
  for (unsigned int r = 0; r < 3; ++r)
  {
    towardsSource[r] = m_FocalPoint[r] - centreInRoom[r];
    isocenter[r] = centreInRoom[r];
  }
  const double distance = towardsSource.GetNorm();
  if (!(distance > 1.05 * radius))
  {
    itkExceptionMacro("the focal point (" << m_FocalPoint << ") is inside or next to the volume's bounding sphere ("
                                          << radius << " mm about " << centreInRoom
                                          << "): no virtual detector sees the whole volume; give one with "
                                             "SetDetectorGeometry() or SetDetectorFromImage()");
  }
  towardsSource /= distance;
  DRRProjectionGeometry::VectorType viewUp;
  viewUp.Fill(0.0);
  viewUp[std::abs(towardsSource[2]) > 0.9 ? 1 : 2] = 1.0;
  // 10% wider than the sphere's shadow (room for the pose to move), behind the whole sphere.
  const double sid = distance + 1.1 * radius;
  const double halfAngle = std::asin(radius / distance);
  const double halfWidth = 1.1 * sid * std::tan(halfAngle);
  auto         geometry = GeometryType::New();
  geometry->SetProjection(PointBasedDRREnums::Projection::Perspective);
  geometry->SetIsocenter(isocenter);
  geometry->SetNormal(towardsSource);
  geometry->SetViewUp(viewUp);
  geometry->SetSourceToIsocenterDistance(distance);
  geometry->SetSourceToDetectorDistance(sid);
  geometry->SetDetectorSize({ { m_DetectorSize, m_DetectorSize } });
  geometry->SetDetectorSpacing(DRRProjectionGeometry::DetectorVectorType(2.0 * halfWidth / m_DetectorSize));
  geometry->VerifyGeometry();
  m_Geometry = geometry;
}

template <typename TInputImage, typename TCoordinate>
auto
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::GetProjection() const -> const ProjectionImageType *
{
  this->UpdateProjection();
  const std::lock_guard<std::mutex> lock(GetRenderMutex());
  if (m_Filter->GetGeometry() != m_Geometry.GetPointer())
  {
    // A shared filter last rendered another interpolator's view: render this one's again.
    m_Filter->SetGeometry(m_Geometry);
    m_Filter->Update();
  }
  return m_Filter->GetOutput();
}

template <typename TInputImage, typename TCoordinate>
auto
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::Evaluate(const PointType & point) const -> OutputType
{
  this->UpdateProjection();
  // CT -> room, then where the ray from the source through it meets the detector plane.
  Vector<double, 3> fromSource;
  for (unsigned int r = 0; r < 3; ++r)
  {
    fromSource[r] = m_VolumeToRoomOffset[r] + m_VolumeToRoomMatrix[r][0] * point[0] +
                    m_VolumeToRoomMatrix[r][1] * point[1] + m_VolumeToRoomMatrix[r][2] * point[2] - m_Source[r];
  }
  const double depth = -(fromSource * m_Normal);
  if (!(depth > 0.0))
  {
    return 0.0; // the ray leaves the source away from the detector
  }
  const Point<double, 3>  onDetector = m_Source + fromSource * (m_SourceToDetectorDistance / depth);
  const Vector<double, 3> fromPixel00 = onDetector - m_Pixel00;
  const double            column = fromPixel00 * m_ColumnStep;
  const double            row = fromPixel00 * m_RowStep;
  // Bilinear interpolation between pixel centres; zero beyond the outer pixel centres' half pixel.
  const double c0 = std::floor(column);
  const double r0 = std::floor(row);
  if (!(c0 >= -1.0 && r0 >= -1.0 && c0 < m_Columns && r0 < m_Rows))
  {
    return 0.0;
  }
  const int    c = static_cast<int>(c0);
  const int    r = static_cast<int>(r0);
  const double fc = column - c0;
  const double fr = row - r0;
  const auto   value = [this](int cc, int rr) -> double {
    return cc >= 0 && rr >= 0 && cc < m_Columns && rr < m_Rows ? m_Values[cc + static_cast<size_t>(rr) * m_Columns]
                                                                 : 0.0;
  };
  return (1.0 - fc) * ((1.0 - fr) * value(c, r) + fr * value(c, r + 1)) +
         fc * ((1.0 - fr) * value(c + 1, r) + fr * value(c + 1, r + 1));
}

template <typename TInputImage, typename TCoordinate>
auto
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::EvaluateAtContinuousIndex(
  const ContinuousIndexType & index) const -> OutputType
{
  PointType point;
  this->GetInputImage()->TransformContinuousIndexToPhysicalPoint(index, point);
  return this->Evaluate(point);
}

template <typename TInputImage, typename TCoordinate>
void
PointBasedDRRInterpolateImageFunction<TInputImage, TCoordinate>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "FocalPoint: " << m_FocalPoint << std::endl;
  os << indent << "Threshold: " << m_Threshold << std::endl;
  os << indent << "AttenuationFromThreshold: " << (m_AttenuationFromThreshold ? "On" : "Off") << std::endl;
  os << indent << "Transform: " << m_Transform.GetPointer() << std::endl;
  os << indent << "Detector: " << (m_AutomaticDetector ? "automatic, " : "given, ") << m_DetectorSize << std::endl;
  os << indent << "NumberOfRenders: " << m_NumberOfRenders << std::endl;
  os << indent << "DRRFilter: " << std::endl;
  m_Filter->Print(os, indent.GetNextIndent());
}
} // namespace itk

#endif
