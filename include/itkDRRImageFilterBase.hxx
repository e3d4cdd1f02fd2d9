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
#ifndef itkDRRImageFilterBase_hxx
#define itkDRRImageFilterBase_hxx

#include "itkDRRImageFilterBase.h"
#include "itkDRROutputConversion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
template <typename TInputImage, typename TOutputImage>
DRRImageFilterBase<TInputImage, TOutputImage>::DRRImageFilterBase()
  : m_Geometry(GeometryType::New()), m_AttenuationVolumeFilter(AttenuationVolumeFilterType::New())
{
  // The input volume, or a shared attenuation model (VerifyPreconditions()).
  this->SetNumberOfRequiredInputs(0);
  this->ProcessObject::SetOutput("Channels", this->MakeOutput("Channels"));
  this->ProcessObject::SetOutput("ChannelCovariance", this->MakeOutput("ChannelCovariance"));
}

template <typename TInputImage, typename TOutputImage>
DataObject::Pointer
DRRImageFilterBase<TInputImage, TOutputImage>::MakeOutput(const ProcessObject::DataObjectIdentifierType & name)
{
  if (name == "Channels" || name == "ChannelCovariance")
  {
    return ChannelImageType::New().GetPointer();
  }
  return Superclass::MakeOutput(name);
}

template <typename TInputImage, typename TOutputImage>
auto
DRRImageFilterBase<TInputImage, TOutputImage>::GetChannelOutput() -> ChannelImageType *
{
  return dynamic_cast<ChannelImageType *>(this->ProcessObject::GetOutput("Channels"));
}

template <typename TInputImage, typename TOutputImage>
auto
DRRImageFilterBase<TInputImage, TOutputImage>::GetChannelCovarianceOutput() -> ChannelImageType *
{
  return dynamic_cast<ChannelImageType *>(this->ProcessObject::GetOutput("ChannelCovariance"));
}

template <typename TInputImage, typename TOutputImage>
ModifiedTimeType
DRRImageFilterBase<TInputImage, TOutputImage>::GetMTime() const
{
  ModifiedTimeType latest = Superclass::GetMTime();
  if (m_Geometry)
  {
    latest = std::max(latest, m_Geometry->GetMTime());
  }
  if (m_Transform)
  {
    latest = std::max(latest, m_Transform->GetMTime());
  }
  // The stage's settings and transfer function: a change there re-renders (the stage's own update then rebuilds the
  // model). Its inputs are this filter's, which the pipeline compares itself.
  return std::max(latest, m_AttenuationVolumeFilter->GetMTime());
}

template <typename TInputImage, typename TOutputImage>
const DRRAttenuationVolume *
DRRImageFilterBase<TInputImage, TOutputImage>::GetSharedAttenuationVolume() const
{
  return itkDynamicCastInDebugMode<const DRRAttenuationVolume *>(this->ProcessObject::GetInput("AttenuationVolume"));
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  const bool gray = m_OutputMode == OutputModeEnum::Gray8 || m_OutputMode == OutputModeEnum::Gray16;
  if (!gray && std::numeric_limits<OutputPixelType>::is_integer)
  {
    itkExceptionMacro("an integer output pixel type holds only the Gray8 or Gray16 output modes, not " << m_OutputMode);
  }
  if (m_NumberOfStreamDivisions > 1)
  {
    const std::string why = this->WhyNotStreamable();
    if (!why.empty())
    {
      itkExceptionMacro("" << why);
    }
  }
  if (!this->GetSharedAttenuationVolume())
  {
    if (!this->GetInput())
    {
      itkExceptionMacro("no input volume (SetInput()) and no attenuation volume (SetAttenuationVolume())");
    }
    return;
  }
  if (this->GetInput())
  {
    itkExceptionMacro("both an input volume and a shared attenuation volume are set: give one (the attenuation "
                      "volume's filter takes the volume)");
  }
  if (this->GetLabelImage() || !this->GetKeptLabels().empty() || !this->GetDroppedLabels().empty() ||
      this->GetLabelChannels() || this->GetMaterialChannels())
  {
    itkExceptionMacro("labels and channels belong to the shared attenuation volume's filter "
                      "(DRRImageToAttenuationVolumeFilter), not to a filter given its output");
  }
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::GenerateOutputInformation()
{
  if (!m_Geometry)
  {
    itkExceptionMacro("no projection geometry set");
  }
  m_Geometry->VerifyGeometry();
  const auto & detectorSize = m_Geometry->GetDetectorSize();
  const auto & detectorSpacing = m_Geometry->GetDetectorSpacing();

  typename OutputImageType::SizeType      size;
  typename OutputImageType::IndexType     start;
  typename OutputImageType::SpacingType   spacing;
  typename OutputImageType::PointType     origin;
  typename OutputImageType::DirectionType direction;
  start.Fill(0);
  direction.SetIdentity();
  for (unsigned int d = 0; d < 2; ++d)
  {
    size[d] = detectorSize[d];
    spacing[d] = detectorSpacing[d];
  }
  if (OutputImageDimension == 2)
  {
    const auto origin2D = m_Geometry->GetDetectorOrigin2D();
    origin[0] = origin2D[0];
    origin[1] = origin2D[1];
  }
  else
  {
    // One slice placed in the room: origin at pixel (0, 0), axes (u, v, -n).
    const auto u = m_Geometry->GetColumnDirection();
    const auto v = m_Geometry->GetRowDirection();
    const auto n = m_Geometry->GetNormal();
    const auto pixel00 = m_Geometry->GetPixelCenter(0.0, 0.0);
    for (unsigned int r = 0; r < 3; ++r)
    {
      origin[r] = pixel00[r];
      direction[r][0] = u[r];
      direction[r][1] = v[r];
      direction[r][2] = -n[r];
    }
    size[OutputImageDimension - 1] = 1;
    spacing[OutputImageDimension - 1] = 1.0;
  }
  const OutputImageRegionType                    region(start, size);
  std::vector<ImageBase<OutputImageDimension> *> outputs{ this->GetChannelOutput(),
                                                          this->GetChannelCovarianceOutput() };
  for (unsigned int i = 0; i < this->GetNumberOfIndexedOutputs(); ++i)
  {
    outputs.push_back(this->GetOutput(i));
  }
  for (ImageBase<OutputImageDimension> * output : outputs)
  {
    if (output)
    {
      output->SetLargestPossibleRegion(region);
      output->SetSpacing(spacing);
      output->SetOrigin(origin);
      output->SetDirection(direction);
    }
  }
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  // The stage checks the input's file, before this filter asks for the input (a slab) itself.
  this->ConnectStage()->VerifyInputFile();
  auto * input = const_cast<InputImageType *>(this->GetInput());
  if (input && this->GetNumberOfSlabs() > 1)
  {
    // Streaming: the first slab, or what the input holds if the update reads no slab (nothing is read then).
    const auto buffered = input->GetBufferedRegion();
    const bool holdsSome = buffered.GetNumberOfPixels() > 0 && input->GetLargestPossibleRegion().IsInside(buffered);
    input->SetRequestedRegion(!this->ReadsSlabsAtNextUpdate() && holdsSome ? buffered : this->GetSlabRegion(0));
  }
  else if (input)
  {
    input->SetRequestedRegionToLargestPossibleRegion();
  }
  auto * labels = const_cast<LabelImageType *>(this->GetLabelImage());
  if (labels && input)
  {
    // The labels of the voxels asked for: the same planes of labels on the volume's grid, else (and for label
    // channels, numbered by the labels of the whole volume) the whole image.
    labels->SetRequestedRegion(this->GetLabelChannels() ? labels->GetLargestPossibleRegion()
                                                        : AttenuationVolumeFilterType::LabelRegionOf(
                                                            *input, *labels, input->GetRequestedRegion()));
  }
  else if (labels)
  {
    labels->SetRequestedRegionToLargestPossibleRegion();
  }
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::EnlargeOutputRequestedRegion(DataObject * output)
{
  Superclass::EnlargeOutputRequestedRegion(output);
  output->SetRequestedRegionToLargestPossibleRegion();
}

template <typename TInputImage, typename TOutputImage>
const DRRAttenuationVolume *
DRRImageFilterBase<TInputImage, TOutputImage>::GetAttenuationVolume()
{
  if (const DRRAttenuationVolume * shared = this->GetSharedAttenuationVolume())
  {
    // Through its source, if stale: the whole volume.
    auto * model = const_cast<DRRAttenuationVolume *>(shared);
    model->UpdateOutputInformation();
    model->SetRequestedRegionToLargestPossibleRegion();
    model->Update();
    return shared;
  }
  AttenuationVolumeFilterType * stage = this->ConnectStage();
  stage->UpdateLargestPossibleRegion(); // the whole volume, after slabs too
  return stage->GetOutput();
}

template <typename TInputImage, typename TOutputImage>
auto
DRRImageFilterBase<TInputImage, TOutputImage>::ConnectStage() -> AttenuationVolumeFilterType *
{
  AttenuationVolumeFilterType * stage = m_AttenuationVolumeFilter.GetPointer();
  stage->SetInput(this->GetInput());
  stage->SetLabelImage(this->GetLabelImage());
  stage->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  return stage;
}

template <typename TInputImage, typename TOutputImage>
auto
DRRImageFilterBase<TInputImage, TOutputImage>::GetChannelLabels() const -> const LabelListType &
{
  const DRRAttenuationVolume * shared = this->GetSharedAttenuationVolume();
  return (shared ? shared : m_AttenuationVolumeFilter->GetOutput())->GetChannelLabels();
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::ComputeTransformAffine(DRRPointProjection::MatrixType & matrix,
                                                                      DRRPointProjection::VectorType & offset) const
{
  matrix.SetIdentity();
  offset.Fill(0.0);
  if (!m_Transform)
  {
    return;
  }
  if (!m_Transform->IsLinear())
  {
    itkExceptionMacro("the transform " << m_Transform->GetNameOfClass()
                                       << " is not linear; DRR filters accept linear (rigid, affine) transforms");
  }
  typename TransformType::InputPointType zero;
  zero.Fill(0.0);
  const auto image0 = m_Transform->TransformPoint(zero);
  for (unsigned int c = 0; c < 3; ++c)
  {
    typename TransformType::InputPointType unit = zero;
    unit[c] = 1.0;
    const auto imageC = m_Transform->TransformPoint(unit);
    for (unsigned int r = 0; r < 3; ++r)
    {
      matrix[r][c] = imageC[r] - image0[r];
    }
  }
  for (unsigned int r = 0; r < 3; ++r)
  {
    offset[r] = image0[r];
  }
}

template <typename TInputImage, typename TOutputImage>
unsigned int
DRRImageFilterBase<TInputImage, TOutputImage>::GetNumberOfSlabs() const
{
  const InputImageType * input = this->GetInput();
  if (!input)
  {
    return 1;
  }
  const auto largest = input->GetLargestPossibleRegion();
  // The budget streams what can be streamed; the rest is rendered whole, as before there was a budget.
  const unsigned int forBudget =
    this->WhyNotStreamable().empty()
      ? DRRMemoryBudget::ComputeNumberOfSlabs(largest.GetNumberOfPixels(), this->GetBytesPerVoxel(), m_MemoryBudget)
      : 1;
  const unsigned int wanted = std::max(m_NumberOfStreamDivisions, forBudget);
  if (wanted <= 1)
  {
    return 1;
  }
  const uint64_t planes = largest.GetSize()[2];
  const uint64_t alignment = std::max<uint64_t>(this->GetSlabAlignment(), 1);
  const uint64_t blocks = std::max<uint64_t>((planes + alignment - 1) / alignment, 1);
  return static_cast<unsigned int>(std::min<uint64_t>(wanted, blocks));
}

template <typename TInputImage, typename TOutputImage>
std::string
DRRImageFilterBase<TInputImage, TOutputImage>::WhyNotStreamable() const
{
  if (this->GetSharedAttenuationVolume())
  {
    return "streaming reads the input volume slab by slab: a shared attenuation volume is already whole";
  }
  return {};
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::GetSlabPlanes(unsigned int slab,
                                                             unsigned int slabs,
                                                             uint64_t &   first,
                                                             uint64_t &   end) const
{
  const uint64_t planes = this->GetInput()->GetLargestPossibleRegion().GetSize()[2];
  const uint64_t alignment = std::max<uint64_t>(this->GetSlabAlignment(), 1);
  const uint64_t blocks = (planes + alignment - 1) / alignment;
  first = std::min(planes, alignment * (blocks * slab / slabs));
  end = std::min(planes, alignment * (blocks * (slab + 1) / slabs));
}

template <typename TInputImage, typename TOutputImage>
auto
DRRImageFilterBase<TInputImage, TOutputImage>::GetSlabRegion(unsigned int slab) const ->
  typename InputImageType::RegionType
{
  auto     region = this->GetInput()->GetLargestPossibleRegion();
  uint64_t first = 0;
  uint64_t end = 0;
  this->GetSlabPlanes(slab, this->GetNumberOfSlabs(), first, end);
  region.SetIndex(2, region.GetIndex()[2] + static_cast<IndexValueType>(first));
  region.SetSize(2, static_cast<SizeValueType>(end - first));
  return region;
}

template <typename TInputImage, typename TOutputImage>
unsigned int
DRRImageFilterBase<TInputImage, TOutputImage>::GetCurrentSlab() const
{
  const InputImageType * input = this->GetInput();
  const auto &           asked = m_AttenuationVolumeFilter->GetOutput()->GetRequestedRegion();
  if (!input || asked.GetNumberOfPixels() == 0 || asked == input->GetLargestPossibleRegion())
  {
    return 0;
  }
  const unsigned int slabs = this->GetNumberOfSlabs();
  const uint64_t asked0 = static_cast<uint64_t>(asked.GetIndex()[2] - input->GetLargestPossibleRegion().GetIndex()[2]);
  for (unsigned int slab = 0; slab < slabs; ++slab)
  {
    uint64_t first = 0;
    uint64_t end = 0;
    this->GetSlabPlanes(slab, slabs, first, end);
    if (first == asked0 && end - first == asked.GetSize()[2])
    {
      return slab + 1;
    }
  }
  return 0;
}

template <typename TInputImage, typename TOutputImage>
DRRAttenuationVolume::Pointer
DRRImageFilterBase<TInputImage, TOutputImage>::ReadSlab(unsigned int slab)
{
  // ITK's streaming (as ImageSink): the stage is asked for the slab's region, and its pipeline reads the slab.
  DRRAttenuationVolume * model = this->ConnectStage()->GetOutput();
  model->UpdateOutputInformation();
  model->SetRequestedRegion(this->GetSlabRegion(slab));
  model->Update();
  return model;
}

template <typename TInputImage, typename TOutputImage>
ModifiedTimeType
DRRImageFilterBase<TInputImage, TOutputImage>::GetModelMadeOfTime() const
{
  const auto madeBy = [](const DataObject * data) -> ModifiedTimeType {
    return !data ? 0 : data->GetSource() ? data->GetPipelineMTime() : data->GetMTime();
  };
  // The stage's time holds its transfer function's (DRRImageToAttenuationVolumeFilter::GetMTime()).
  return std::max({ m_AttenuationVolumeFilter->GetMTime(), madeBy(this->GetInput()), madeBy(this->GetLabelImage()) });
}

template <typename TInputImage, typename TOutputImage>
DRRAttenuationVolume::Pointer
DRRImageFilterBase<TInputImage, TOutputImage>::MakeInputGrid() const
{
  const InputImageType * input = this->GetInput();
  auto                   grid = DRRAttenuationVolume::New();
  AttenuationVolumeFilterType::SetIndexToPhysical(*input, input->GetLargestPossibleRegion().GetIndex(), *grid);
  return grid;
}

template <typename TInputImage, typename TOutputImage>
DRRPointProjection
DRRImageFilterBase<TInputImage, TOutputImage>::MakeProjection()
{
  return this->MakeProjection(*this->GetAttenuationVolume());
}

template <typename TInputImage, typename TOutputImage>
DRRPointProjection
DRRImageFilterBase<TInputImage, TOutputImage>::MakeProjection(const DRRAttenuationVolume & volume) const
{
  DRRPointProjection::MatrixType matrix;
  DRRPointProjection::VectorType offset;
  this->ComputeTransformAffine(matrix, offset);
  return DRRPointProjection(*m_Geometry, volume, matrix, offset);
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::WriteOutputs(const std::vector<double> & lineIntegral,
                                                            const std::vector<double> * standardError)
{
  const bool gray = m_OutputMode == OutputModeEnum::Gray8 || m_OutputMode == OutputModeEnum::Gray16;
  double     low = m_WindowLevel - 0.5 * m_WindowWidth;
  double     width = m_WindowWidth;
  const auto notFiniteIntegral =
    std::find_if(lineIntegral.begin(), lineIntegral.end(), [](double v) { return !std::isfinite(v); });
  if (gray && !(width > 0.0) && notFiniteIntegral == lineIntegral.end())
  {
    DRROutputConversion::ComputeAutomaticWindow(lineIntegral.begin(), lineIntegral.end(), low, width);
  }
  const DRROutputConversion conversion(m_OutputMode, low, width > 0.0 ? width : 1.0);

  // A value the output pixel type cannot hold (a finite line integral of 1e44 in float) would become infinite.
  const double largest = static_cast<double>(std::numeric_limits<OutputPixelType>::max());
  if (gray && conversion.GetMaximum() > largest)
  {
    itkExceptionMacro("the output pixel type cannot hold the gray levels of " << m_OutputMode << " (up to "
                                                                              << conversion.GetMaximum() << ")");
  }
  const auto notFinite = notFiniteIntegral != lineIntegral.end()
                           ? notFiniteIntegral
                           : std::find_if(lineIntegral.begin(), lineIntegral.end(), [&](double v) {
                               return !(std::abs(conversion.Value(v)) <= largest);
                             });
  if (notFinite != lineIntegral.end())
  {
    itkExceptionMacro("the projection has a non-finite value, or one the output pixel type cannot hold ("
                      << *notFinite << "), at pixel " << notFinite - lineIntegral.begin()
                      << ": the attenuation or the geometry is out of range");
  }
  OutputPixelType * values = this->AllocateOutput(0, lineIntegral.size());
  OutputPixelType * errors = standardError ? this->AllocateOutput(1, lineIntegral.size()) : nullptr;
  for (size_t p = 0; p < lineIntegral.size(); ++p)
  {
    values[p] = static_cast<OutputPixelType>(conversion.Value(lineIntegral[p]));
    if (errors)
    {
      const double error = conversion.Slope(lineIntegral[p]) * (*standardError)[p];
      if (!(std::abs(error) <= largest))
      {
        itkExceptionMacro("the standard error at pixel " << p << " (" << error
                                                         << ") is not finite or beyond the output pixel type");
      }
      errors[p] =
        static_cast<OutputPixelType>(gray ? std::min(conversion.GetMaximum(), std::floor(error + 0.5)) : error);
    }
  }
}
template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::WriteChannelOutputs(const std::vector<double> & channels,
                                                                   const std::vector<double> * covariance)
{
  const size_t K = this->GetChannelLabels().size();
  for (ChannelImageType * output : { this->GetChannelOutput(), this->GetChannelCovarianceOutput() })
  {
    const bool   isCovariance = output == this->GetChannelCovarianceOutput();
    const size_t components = isCovariance ? K * (K + 1) / 2 : K;
    if (K == 0)
    {
      output->SetBufferedRegion(OutputImageRegionType());
      output->Initialize();
      continue;
    }
    output->SetNumberOfComponentsPerPixel(static_cast<unsigned int>(components));
    output->SetBufferedRegion(output->GetRequestedRegion());
    output->Allocate();
    const size_t                values = output->GetBufferedRegion().GetNumberOfPixels() * components;
    const std::vector<double> * source = isCovariance ? covariance : &channels;
    if (source && source->size() != values)
    {
      itkExceptionMacro("internal error: " << source->size() << " channel values for an output of " << values);
    }
    float * buffer = output->GetBufferPointer();
    for (size_t i = 0; i < values; ++i)
    {
      const double value = source ? (*source)[i] : 0.0;
      if (!std::isfinite(value) || !(std::abs(value) <= std::numeric_limits<float>::max()))
      {
        itkExceptionMacro("channel value " << i % components << " of pixel " << i / components << " (" << value
                                           << ") is not finite or beyond float");
      }
      buffer[i] = static_cast<float>(value);
    }
  }
}

template <typename TInputImage, typename TOutputImage>
auto
DRRImageFilterBase<TInputImage, TOutputImage>::AllocateOutput(unsigned int index, size_t numberOfPixels)
  -> OutputPixelType *
{
  OutputImageType * output = this->GetOutput(index);
  output->SetBufferedRegion(output->GetRequestedRegion());
  output->Allocate();
  if (output->GetBufferedRegion().GetNumberOfPixels() != numberOfPixels)
  {
    itkExceptionMacro("internal error: projection of " << numberOfPixels << " pixels for an output of "
                                                       << output->GetBufferedRegion().GetNumberOfPixels());
  }
  return output->GetBufferPointer();
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Geometry:" << std::endl;
  m_Geometry->Print(os, indent.GetNextIndent());
  os << indent << "Transform: " << (m_Transform ? m_Transform->GetNameOfClass() : "(none)") << std::endl;
  os << indent << "OutputMode: " << m_OutputMode << std::endl;
  os << indent << "WindowLevel: " << m_WindowLevel << std::endl;
  os << indent << "WindowWidth: " << m_WindowWidth << std::endl;
  os << indent << "NumberOfStreamDivisions: " << m_NumberOfStreamDivisions << std::endl;
  os << indent << "MemoryBudget (bytes): " << m_MemoryBudget << std::endl;
  os << indent << "AttenuationVolume: " << (this->GetSharedAttenuationVolume() ? "shared" : "its own stage's")
     << std::endl;
  os << indent << "AttenuationVolumeFilter:" << std::endl;
  m_AttenuationVolumeFilter->Print(os, indent.GetNextIndent());
  os << indent << "ChannelLabels: " << DRRLabelSelection::ToString(this->GetChannelLabels()) << std::endl;
}
} // namespace itk

#endif
