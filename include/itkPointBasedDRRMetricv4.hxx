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
#ifndef itkPointBasedDRRMetricv4_hxx
#define itkPointBasedDRRMetricv4_hxx

#include "itkDRRSamplerFactory.h"
#include "itkEuler3DTransform.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace itk
{
template <typename TVolumeImage>
PointBasedDRRMetricv4<TVolumeImage>::PointBasedDRRMetricv4()
  : m_Sampler(DRRSamplerFactory::Create(DRRSamplerFactory::DefaultName))
  , m_MultiThreader(MultiThreaderBase::New())
  , m_Engine(new DRRKeptPointSimilarity)
{}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::SetVolume(const VolumeImageType * volume)
{
  if (volume != m_Volume.GetPointer() || m_AttenuationVolume)
  {
    m_Volume = volume;
    m_AttenuationVolume = nullptr;
    this->Modified();
  }
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::SetAttenuationVolume(const AttenuationVolumeType * model)
{
  if (model != m_AttenuationVolume.GetPointer() || m_Volume)
  {
    m_AttenuationVolume = model;
    m_Volume = nullptr;
    this->Modified();
  }
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::AddXRay(const XRayImageType * image, const GeometryType * geometry)
{
  m_XRays.push_back({ image, geometry });
  this->Modified();
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::RemoveAllXRays()
{
  m_XRays.clear();
  this->Modified();
}

template <typename TVolumeImage>
unsigned int
PointBasedDRRMetricv4<TVolumeImage>::GetNumberOfXRays() const
{
  return static_cast<unsigned int>(m_XRays.size());
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetXRayImage(unsigned int index) const -> const XRayImageType *
{
  return index < m_XRays.size() ? m_XRays[index].Image.GetPointer() : nullptr;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetXRayGeometry(unsigned int index) const -> const GeometryType *
{
  return index < m_XRays.size() ? m_XRays[index].Geometry.GetPointer() : nullptr;
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::SetNumberOfWorkUnits(ThreadIdType numberOfWorkUnits)
{
  const ThreadIdType clamped = std::max<ThreadIdType>(1, std::min<ThreadIdType>(numberOfWorkUnits, ITK_MAX_THREADS));
  m_MultiThreader->SetMaximumNumberOfThreads(clamped);
  m_MultiThreader->SetNumberOfWorkUnits(clamped);
  this->Modified();
}

template <typename TVolumeImage>
ThreadIdType
PointBasedDRRMetricv4<TVolumeImage>::GetNumberOfWorkUnits() const
{
  return m_MultiThreader->GetMaximumNumberOfThreads();
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetAttenuationModel() const -> const AttenuationVolumeType *
{
  return m_AttenuationVolume ? m_AttenuationVolume.GetPointer() : (m_Stage ? m_Stage->GetOutput() : nullptr);
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::Initialize()
{
  if (m_AttenuationVolume)
  {
    const_cast<AttenuationVolumeType *>(m_AttenuationVolume.GetPointer())->Update(); // through its source, if stale
  }
  else if (m_Volume)
  {
    if (!m_Stage)
    {
      m_Stage = StageType::New();
    }
    m_Stage->SetInput(m_Volume);
    m_Stage->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
    if (m_TransferFunction)
    {
      m_Stage->SetTransferFunction(m_TransferFunction);
    }
    m_Stage->Update();
  }
  else
  {
    itkExceptionMacro("no CT (SetVolume()) and no attenuation model (SetAttenuationVolume())");
  }
  if (!m_Sampler)
  {
    itkExceptionMacro("no sampler (SetSampler())");
  }
  const AttenuationVolumeType * model = this->GetAttenuationModel();
  if (!m_MovingTransform)
  {
    auto transform = Euler3DTransform<double>::New();
    transform->SetCenter(this->ComputeVolumeCenter());
    m_MovingTransform = transform;
  }
  DRRKeptPointSimilarity::Settings settings;
  settings.Similarity = m_Similarity;
  settings.NumberOfSamples = m_NumberOfSamples;
  settings.Seed = m_Seed;
  settings.Kernel = m_ReconstructionKernel;
  settings.ShrinkFactor = m_DetectorShrinkFactor;
  settings.SmoothingSigma = m_SmoothingSigma;
  settings.ExactRaysPerPixelSide = m_ExactRaysPerPixelSide;
  m_Engine->Prepare(
    *model, model->GetMTime(), *m_Sampler, m_XRays, settings, *m_MovingTransform, m_MultiThreader.GetPointer());
  m_Similarities.assign(m_XRays.size(), 0.0);
  m_NumberOfValueEvaluations = 0;
  m_NumberOfDerivativeEvaluations = 0;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::Evaluate(DerivativeType * derivative) const -> MeasureType
{
  if (!m_MovingTransform)
  {
    itkExceptionMacro("no moving transform: call Initialize() first");
  }
  std::vector<DRRKeptPointSimilarity::ViewResult> views;
  const double similarity = m_Engine->Evaluate(*m_MovingTransform, derivative, &views, m_MultiThreader.GetPointer());
  m_Similarities.resize(views.size());
  for (size_t v = 0; v < views.size(); ++v)
  {
    m_Similarities[v] = views[v].Similarity;
  }
  // Minimized: minus the similarity; the v4 derivative is the negative of the value's, + dS/dtheta.
  this->m_Value = -similarity;
  ++(derivative ? m_NumberOfDerivativeEvaluations : m_NumberOfValueEvaluations);
  return this->m_Value;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetValue() const -> MeasureType
{
  return this->Evaluate(nullptr);
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::GetDerivative(DerivativeType & derivative) const
{
  this->Evaluate(&derivative);
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::GetValueAndDerivative(MeasureType & value, DerivativeType & derivative) const
{
  value = this->Evaluate(&derivative);
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetNumberOfParameters() const -> NumberOfParametersType
{
  return m_MovingTransform ? m_MovingTransform->GetNumberOfParameters() : 0;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetNumberOfLocalParameters() const -> NumberOfParametersType
{
  return this->GetNumberOfParameters();
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::SetParameters(ParametersType & parameters)
{
  if (!m_MovingTransform)
  {
    itkExceptionMacro("no moving transform: call Initialize() first");
  }
  m_MovingTransform->SetParameters(parameters);
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetParameters() const -> const ParametersType &
{
  if (!m_MovingTransform)
  {
    itkExceptionMacro("no moving transform: call Initialize() first");
  }
  return m_MovingTransform->GetParameters();
}

template <typename TVolumeImage>
bool
PointBasedDRRMetricv4<TVolumeImage>::HasLocalSupport() const
{
  return false;
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::UpdateTransformParameters(const DerivativeType & update,
                                                               ParametersValueType    factor)
{
  if (!m_MovingTransform)
  {
    itkExceptionMacro("no moving transform: call Initialize() first");
  }
  m_MovingTransform->UpdateTransformParameters(update, factor);
}

template <typename TVolumeImage>
double
PointBasedDRRMetricv4<TVolumeImage>::GetSimilarity(unsigned int index) const
{
  return index < m_Similarities.size() ? m_Similarities[index] : 0.0;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::ComputeDRR(unsigned int index) const -> typename XRayImageType::Pointer
{
  const GeometryType * geometry = m_Engine->GetBinnedGeometry(index);
  if (!geometry)
  {
    itkExceptionMacro("no X-ray " << index << " prepared (" << m_XRays.size() << " X-rays; Initialize() first)");
  }
  std::vector<DRRKeptPointSimilarity::ViewResult> views;
  m_Engine->Evaluate(*m_MovingTransform, nullptr, &views, m_MultiThreader.GetPointer());
  auto                                image = XRayImageType::New();
  typename XRayImageType::SizeType    size;
  typename XRayImageType::PointType   origin;
  typename XRayImageType::SpacingType spacing;
  const auto                          corner = geometry->GetDetectorOrigin2D();
  for (unsigned int d = 0; d < 2; ++d)
  {
    size[d] = geometry->GetDetectorSize()[d];
    spacing[d] = geometry->GetDetectorSpacing()[d];
    origin[d] = corner[d];
  }
  image->SetRegions(size);
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->Allocate();
  std::copy(views[index].DRR.begin(), views[index].DRR.end(), image->GetBufferPointer());
  return image;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::GetField(unsigned int index) const -> typename MaskImageType::Pointer
{
  const GeometryType * geometry = m_Engine->GetBinnedGeometry(index);
  if (!geometry)
  {
    itkExceptionMacro("no X-ray " << index << " prepared (" << m_XRays.size() << " X-rays; Initialize() first)");
  }
  auto                                mask = MaskImageType::New();
  typename MaskImageType::SizeType    size;
  typename MaskImageType::PointType   origin;
  typename MaskImageType::SpacingType spacing;
  const auto                          corner = geometry->GetDetectorOrigin2D();
  for (unsigned int d = 0; d < 2; ++d)
  {
    size[d] = geometry->GetDetectorSize()[d];
    spacing[d] = geometry->GetDetectorSpacing()[d];
    origin[d] = corner[d];
  }
  mask->SetRegions(size);
  mask->SetSpacing(spacing);
  mask->SetOrigin(origin);
  mask->Allocate();
  const std::vector<uint8_t> & field = m_Engine->GetField(index);
  std::copy(field.begin(), field.end(), mask->GetBufferPointer());
  return mask;
}

template <typename TVolumeImage>
Point<double, 3>
PointBasedDRRMetricv4<TVolumeImage>::ComputeVolumeCenter() const
{
  if (m_Volume)
  {
    return DRRProjectionGeometry::ComputeImageCenter(m_Volume);
  }
  const AttenuationVolumeType * model = this->GetAttenuationModel();
  if (!model)
  {
    itkExceptionMacro("no CT (SetVolume()) and no attenuation model (SetAttenuationVolume())");
  }
  const auto       size = model->GetSize();
  const auto       matrix = model->GetIndexToPhysicalMatrix();
  Point<double, 3> center = model->GetOrigin();
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 3; ++c)
    {
      center[r] += matrix[r][c] * 0.5 * (static_cast<double>(size[c]) - 1.0);
    }
  }
  return center;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::ComputeSampleMotions() const -> std::vector<vnl_matrix<double>>
{
  const AttenuationVolumeType * model = this->GetAttenuationModel();
  if (!model || !m_MovingTransform)
  {
    itkExceptionMacro("the parameter scales need the model and the transform: call Initialize() first");
  }
  // A few thousand positions (continuous indices) that stand for the attenuation: kept points, or, for the exact
  // projector, the attenuating voxels of a regular subgrid.
  std::vector<std::array<double, 3>> positions;
  if (const DRRPointCloud * cloud = m_Engine->GetPointCloud())
  {
    const uint64_t points = cloud->GetNumberOfPoints();
    for (uint64_t i = 0; i < points; i += std::max<uint64_t>(1, points / 4096))
    {
      positions.push_back({ { cloud->GetX()[i], cloud->GetY()[i], cloud->GetZ()[i] } });
    }
  }
  else
  {
    const auto     size = model->GetSize();
    const uint64_t step = std::max<uint64_t>(
      1, static_cast<uint64_t>(std::cbrt(static_cast<double>(size[0]) * size[1] * size[2] / 4096.0)));
    for (uint64_t k = step / 2; k < size[2]; k += step)
    {
      for (uint64_t j = step / 2; j < size[1]; j += step)
      {
        for (uint64_t i = step / 2; i < size[0]; i += step)
        {
          if (model->GetMuOrZero(i, j, k) > 0.0f)
          {
            positions.push_back({ { static_cast<double>(i), static_cast<double>(j), static_cast<double>(k) } });
          }
        }
      }
    }
  }
  if (positions.empty())
  {
    itkExceptionMacro("the volume has no attenuation to move: no parameter scales");
  }
  DRRPointProjection::MatrixType matrix;
  DRRPointProjection::VectorType offset;
  DRRKeptPointSimilarity::GetLinearPart(*m_MovingTransform, matrix, offset);
  const auto                                 inverse = matrix.GetInverse();
  const auto                                 indexToPhysical = model->GetIndexToPhysicalMatrix();
  const unsigned int                         count = m_MovingTransform->GetNumberOfParameters();
  typename MovingTransformType::JacobianType jacobian;
  std::vector<vnl_matrix<double>>            motions;
  motions.reserve(positions.size());
  for (const auto & index : positions)
  {
    // The position in the CT's frame, then in the room (y = A^-1 (x - b)), where it moves by -A^-1 dT/dtheta.
    double x[3];
    for (unsigned int r = 0; r < 3; ++r)
    {
      x[r] = model->GetOrigin()[r] - offset[r];
      for (unsigned int c = 0; c < 3; ++c)
      {
        x[r] += indexToPhysical[r][c] * index[c];
      }
    }
    Point<double, 3> y;
    for (unsigned int r = 0; r < 3; ++r)
    {
      y[r] = inverse[r][0] * x[0] + inverse[r][1] * x[1] + inverse[r][2] * x[2];
    }
    m_MovingTransform->ComputeJacobianWithRespectToParameters(y, jacobian);
    vnl_matrix<double> motion(3, count);
    for (unsigned int j = 0; j < count; ++j)
    {
      for (unsigned int r = 0; r < 3; ++r)
      {
        motion(r, j) =
          -(inverse[r][0] * jacobian(0, j) + inverse[r][1] * jacobian(1, j) + inverse[r][2] * jacobian(2, j));
      }
    }
    motions.push_back(motion);
  }
  return motions;
}

template <typename TVolumeImage>
auto
PointBasedDRRMetricv4<TVolumeImage>::ComputeParameterScales() const -> ScalesType
{
  const std::vector<vnl_matrix<double>> motions = this->ComputeSampleMotions();
  const unsigned int                    count = this->GetNumberOfParameters();
  ScalesType                            scales(count);
  scales.Fill(0.0);
  for (const vnl_matrix<double> & motion : motions)
  {
    for (unsigned int j = 0; j < count; ++j)
    {
      scales[j] += motion.get_column(j).squared_magnitude() / static_cast<double>(motions.size());
    }
  }
  return scales;
}

template <typename TVolumeImage>
double
PointBasedDRRMetricv4<TVolumeImage>::ComputeMaximumDisplacement(const ParametersType & step) const
{
  const std::vector<vnl_matrix<double>> motions = this->ComputeSampleMotions();
  if (step.GetSize() != this->GetNumberOfParameters())
  {
    itkExceptionMacro("a step of " << step.GetSize() << " parameters for a transform of "
                                   << this->GetNumberOfParameters());
  }
  double largest = 0.0;
  for (const vnl_matrix<double> & motion : motions)
  {
    largest = std::max(largest, (motion * step).magnitude());
  }
  return largest;
}

template <typename TVolumeImage>
const DRRPointCloud *
PointBasedDRRMetricv4<TVolumeImage>::GetPointCloud() const
{
  return m_Engine->GetPointCloud();
}

template <typename TVolumeImage>
unsigned int
PointBasedDRRMetricv4<TVolumeImage>::GetNumberOfPointCloudDraws() const
{
  return m_Engine->GetNumberOfDraws();
}

template <typename TVolumeImage>
void
PointBasedDRRMetricv4<TVolumeImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Volume: " << m_Volume.GetPointer() << std::endl;
  os << indent << "AttenuationVolume: " << m_AttenuationVolume.GetPointer() << std::endl;
  os << indent << "TransferFunction: " << m_TransferFunction.GetPointer() << std::endl;
  os << indent << "NumberOfXRays: " << m_XRays.size() << std::endl;
  os << indent << "MovingTransform: " << m_MovingTransform.GetPointer() << std::endl;
  os << indent << "Similarity: " << m_Similarity << std::endl;
  os << indent << "NumberOfSamples: " << m_NumberOfSamples << std::endl;
  os << indent << "Seed: " << m_Seed << std::endl;
  os << indent << "ReconstructionKernel: " << m_ReconstructionKernel << std::endl;
  os << indent << "Sampler: " << (m_Sampler ? m_Sampler->GetNameOfClass() : "(none)") << std::endl;
  os << indent << "DetectorShrinkFactor: " << m_DetectorShrinkFactor << std::endl;
  os << indent << "SmoothingSigma (mm): " << m_SmoothingSigma << std::endl;
  os << indent << "ExactRaysPerPixelSide: " << m_ExactRaysPerPixelSide << std::endl;
  os << indent << "NumberOfWorkUnits: " << this->GetNumberOfWorkUnits() << std::endl;
  os << indent << "NumberOfValueEvaluations: " << m_NumberOfValueEvaluations << std::endl;
  os << indent << "NumberOfDerivativeEvaluations: " << m_NumberOfDerivativeEvaluations << std::endl;
}
} // namespace itk

#endif
