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
  : m_Geometry(GeometryType::New()), m_TransferFunction(TransferFunctionType::New())
{
  this->SetNumberOfRequiredInputs(1);
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
template <typename TValue>
void
DRRImageFilterBase<TInputImage, TOutputImage>::SetLabelSetting(TValue & member, const TValue & value)
{
  if (value != member)
  {
    member = value;
    m_LabelSelectionTime.Modified(); // the attenuation volume is rebuilt
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::SetKeptLabels(const LabelListType & labels)
{
  this->SetLabelSetting(m_KeptLabels, labels);
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::SetDroppedLabels(const LabelListType & labels)
{
  this->SetLabelSetting(m_DroppedLabels, labels);
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::SetMaterialChannels(bool channels)
{
  this->SetLabelSetting(m_MaterialChannels, channels);
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::SetLabelChannels(bool channels)
{
  this->SetLabelSetting(m_LabelChannels, channels);
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
  if (m_TransferFunction)
  {
    latest = std::max(latest, m_TransferFunction->GetMTime());
  }
  return latest;
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
  auto * input = const_cast<InputImageType *>(this->GetInput());
  if (input)
  {
    input->SetRequestedRegionToLargestPossibleRegion();
  }
  auto * labels = const_cast<LabelImageType *>(this->GetLabelImage());
  if (labels)
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
void
DRRImageFilterBase<TInputImage, TOutputImage>::BuildAttenuationVolume()
{
  const InputImageType * input = this->GetInput();
  if (!input)
  {
    itkExceptionMacro("no input volume");
  }
  const auto region = input->GetLargestPossibleRegion();
  if (region.GetNumberOfPixels() == 0)
  {
    itkExceptionMacro("the input volume is empty (size " << region.GetSize() << ")");
  }
  if (input->GetBufferedRegion() != region)
  {
    itkExceptionMacro("the whole input volume must be buffered (buffered " << input->GetBufferedRegion() << ", largest "
                                                                           << region << ")");
  }

  auto                           volume = DRRAttenuationVolume::New();
  DRRAttenuationVolume::SizeType size;
  for (unsigned int a = 0; a < 3; ++a)
  {
    size[a] = region.GetSize()[a];
  }
  DRRAttenuationVolume::MatrixType indexToPhysical;
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 3; ++c)
    {
      indexToPhysical[r][c] = input->GetDirection()[r][c] * input->GetSpacing()[c];
    }
  }
  typename InputImageType::PointType firstVoxel;
  input->TransformIndexToPhysicalPoint(region.GetIndex(), firstVoxel);
  DRRAttenuationVolume::PointType origin;
  for (unsigned int r = 0; r < 3; ++r)
  {
    origin[r] = firstVoxel[r];
  }
  volume->SetIndexToPhysical(indexToPhysical, origin);

  // On the filter's threads, as many as its work units.
  MultiThreaderBase * threader = this->GetMultiThreader();
  threader->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  // The pixel container keeps the values alive: 16-bit CT is read in place, not copied.
  volume->Build(input->GetBufferPointer(), size, *m_TransferFunction, threader, input->GetPixelContainer());
  this->ApplyLabels(*input, *volume);
  m_AttenuationVolume = volume;
  m_AttenuationVolumeInput = input;
  m_AttenuationVolumeInputTime = input->GetMTime();
  m_AttenuationVolumeTransferTime = m_TransferFunction->GetMTime();
  m_AttenuationVolumeLabelTime = this->GetLabelTime();
  m_AttenuationVolumeLabelImage = this->GetLabelImage();
}

template <typename TInputImage, typename TOutputImage>
ModifiedTimeType
DRRImageFilterBase<TInputImage, TOutputImage>::GetLabelTime() const
{
  const LabelImageType * labels = this->GetLabelImage();
  return std::max<ModifiedTimeType>(m_LabelSelectionTime.GetMTime(), labels ? labels->GetMTime() : 0);
}

template <typename TInputImage, typename TOutputImage>
auto
DRRImageFilterBase<TInputImage, TOutputImage>::LabelsOnVolumeGrid(const InputImageType &        input,
                                                                  std::vector<LabelPixelType> & resampled)
  -> const LabelPixelType *
{
  const LabelImageType * labels = this->GetLabelImage();
  const auto             region = input.GetLargestPossibleRegion();
  const auto             labelRegion = labels->GetLargestPossibleRegion();
  if (labels->GetBufferedRegion() != labelRegion)
  {
    itkExceptionMacro("the whole label image must be buffered");
  }
  const double tolerance = 1e-4 * input.GetSpacing().GetVnlVector().min_value();
  bool         sameGrid =
    region.GetSize() == labelRegion.GetSize() &&
    input.GetOrigin().EuclideanDistanceTo(labels->GetOrigin()) <= tolerance &&
    (input.GetSpacing() - labels->GetSpacing()).GetNorm() <= tolerance &&
    (input.GetDirection().GetVnlMatrix() - labels->GetDirection().GetVnlMatrix()).absolute_value_max() <= 1e-6;
  const size_t numberOfVoxels = region.GetNumberOfPixels();
  if (sameGrid)
  {
    return labels->GetBufferPointer();
  }
  itkWarningMacro("the label image (size "
                  << labelRegion.GetSize() << ", spacing " << labels->GetSpacing() << ", origin " << labels->GetOrigin()
                  << ") is not on the volume's grid (size " << region.GetSize() << ", spacing " << input.GetSpacing()
                  << ", origin " << input.GetOrigin()
                  << "): resampled onto it by nearest neighbour, label 0 outside it");
  resampled.assign(numberOfVoxels, 0);
  const auto size = region.GetSize();
  size_t     inside = 0;
  for (size_t v = 0; v < numberOfVoxels; ++v)
  {
    typename InputImageType::IndexType index;
    index[0] = region.GetIndex()[0] + static_cast<IndexValueType>(v % size[0]);
    index[1] = region.GetIndex()[1] + static_cast<IndexValueType>((v / size[0]) % size[1]);
    index[2] = region.GetIndex()[2] + static_cast<IndexValueType>(v / (size[0] * size[1]));
    typename InputImageType::PointType point;
    input.TransformIndexToPhysicalPoint(index, point);
    typename LabelImageType::IndexType labelIndex;
    if (labels->TransformPhysicalPointToIndex(point, labelIndex))
    {
      resampled[v] = labels->GetPixel(labelIndex);
      ++inside;
    }
  }
  if (inside == 0)
  {
    itkExceptionMacro("the label image (size " << labelRegion.GetSize() << ", origin " << labels->GetOrigin()
                                               << ") covers no voxel of the volume: it belongs to another volume");
  }
  return resampled.data();
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::ApplyLabels(const InputImageType & input, DRRAttenuationVolume & volume)
{
  m_ChannelLabels.clear();
  if (m_MaterialChannels)
  {
    const DRRMaterialTable * table = m_TransferFunction->GetMaterialTable();
    if (m_TransferFunction->GetMode() != DRRTransferFunction::ModeEnum::Materials || !table)
    {
      itkExceptionMacro("material channels need the transfer function's Materials mode (SetMaterialTable())");
    }
    if (m_LabelChannels)
    {
      itkExceptionMacro("material channels and label channels cannot be rendered together");
    }
    const unsigned int K = table->GetNumberOfMaterials();
    if (K > DRRLabelSelection::MaximumNumberOfChannels)
    {
      itkExceptionMacro("" << K << " materials are more channels than a render holds ("
                           << DRRLabelSelection::MaximumNumberOfChannels << ")");
    }
    for (unsigned int m = 0; m < K; ++m)
    {
      m_ChannelLabels.push_back(static_cast<LabelPixelType>(m));
    }
    if (K > 1)
    {
      const InputPixelType * values = input.GetBufferPointer();
      std::vector<uint8_t>   channels(volume.GetNumberOfVoxels());
      const auto             materialOf = [&](double value) {
        return static_cast<uint8_t>(std::max(0, m_TransferFunction->GetMaterialIndex(value)));
      };
      // CT in HU (integers, whatever the pixel type): one lookup per voxel in a table of the int16 range instead of a
      // search of the table's rows; other values search.
      constexpr int32_t    lowest = -32768;
      std::vector<uint8_t> materialOfValue(65536);
      for (int32_t value = lowest; value <= 32767; ++value)
      {
        materialOfValue[static_cast<size_t>(value - lowest)] = materialOf(value);
      }
      DRRAttenuationVolume::ParallelizeBlocks(
        volume.GetNumberOfBlocks(),
        [&](uint64_t block) {
          const uint64_t end = volume.GetBlockBegin(block + 1);
          for (uint64_t v = volume.GetBlockBegin(block); v < end; ++v)
          {
            const double value = static_cast<double>(values[v]);
            const bool   tabled = value >= lowest && value <= 32767.0 && value == std::floor(value);
            channels[v] =
              tabled ? materialOfValue[static_cast<size_t>(static_cast<int32_t>(value) - lowest)] : materialOf(value);
          }
        },
        this->GetMultiThreader());
      volume.SetVoxelChannels(std::move(channels), K);
    }
  }
  if (!this->GetLabelImage())
  {
    if (!m_KeptLabels.empty() || !m_DroppedLabels.empty() || m_LabelChannels)
    {
      itkExceptionMacro("kept or dropped labels and label channels need a label image (SetLabelImage())");
    }
    return;
  }
  std::vector<LabelPixelType> resampled;
  const LabelPixelType *      labels = this->LabelsOnVolumeGrid(input, resampled);
  const LabelListType         channelLabels =
    DRRLabelSelection::Apply(labels, m_KeptLabels, m_DroppedLabels, m_LabelChannels, volume, this->GetMultiThreader());
  if (m_LabelChannels)
  {
    m_ChannelLabels = channelLabels;
  }
}

template <typename TInputImage, typename TOutputImage>
const DRRAttenuationVolume *
DRRImageFilterBase<TInputImage, TOutputImage>::GetAttenuationVolume()
{
  const InputImageType * input = this->GetInput();
  if (!m_AttenuationVolume || input != m_AttenuationVolumeInput || !input ||
      input->GetMTime() != m_AttenuationVolumeInputTime ||
      m_TransferFunction->GetMTime() != m_AttenuationVolumeTransferTime ||
      this->GetLabelTime() != m_AttenuationVolumeLabelTime || this->GetLabelImage() != m_AttenuationVolumeLabelImage)
  {
    this->BuildAttenuationVolume();
  }
  return m_AttenuationVolume.GetPointer();
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
DRRPointProjection
DRRImageFilterBase<TInputImage, TOutputImage>::MakeProjection()
{
  DRRPointProjection::MatrixType matrix;
  DRRPointProjection::VectorType offset;
  this->ComputeTransformAffine(matrix, offset);
  return DRRPointProjection(*m_Geometry, *this->GetAttenuationVolume(), matrix, offset);
}

template <typename TInputImage, typename TOutputImage>
void
DRRImageFilterBase<TInputImage, TOutputImage>::WriteOutputs(const std::vector<double> & lineIntegral,
                                                            const std::vector<double> * standardError)
{
  const bool gray = m_OutputMode == OutputModeEnum::Gray8 || m_OutputMode == OutputModeEnum::Gray16;
  if (!gray && std::numeric_limits<OutputPixelType>::is_integer)
  {
    itkExceptionMacro("an integer output pixel type holds only the Gray8 or Gray16 output modes, not " << m_OutputMode);
  }
  double low = m_WindowLevel - 0.5 * m_WindowWidth;
  double width = m_WindowWidth;
  if (gray && !(width > 0.0))
  {
    const auto range = std::minmax_element(lineIntegral.begin(), lineIntegral.end());
    low = *range.first;
    width = std::max(*range.second - *range.first, std::numeric_limits<double>::min());
  }
  const DRROutputConversion conversion(m_OutputMode, low, width);

  // A value the output pixel type cannot hold (a finite line integral of 1e44 in float) would become infinite.
  const double largest = static_cast<double>(std::numeric_limits<OutputPixelType>::max());
  if (gray && conversion.GetMaximum() > largest)
  {
    itkExceptionMacro("the output pixel type cannot hold the gray levels of " << m_OutputMode << " (up to "
                                                                              << conversion.GetMaximum() << ")");
  }
  const auto notFinite = std::find_if(lineIntegral.begin(), lineIntegral.end(), [&](double v) {
    return !std::isfinite(v) || !(std::abs(conversion.Value(v)) <= largest);
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
  const size_t K = m_ChannelLabels.size();
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
  os << indent << "TransferFunction:" << std::endl;
  m_TransferFunction->Print(os, indent.GetNextIndent());
  os << indent << "OutputMode: " << m_OutputMode << std::endl;
  os << indent << "WindowLevel: " << m_WindowLevel << std::endl;
  os << indent << "WindowWidth: " << m_WindowWidth << std::endl;
  os << indent << "LabelImage: " << (this->GetLabelImage() ? "set" : "(none)") << std::endl;
  os << indent << "KeptLabels: " << DRRLabelSelection::ToString(m_KeptLabels) << std::endl;
  os << indent << "DroppedLabels: " << DRRLabelSelection::ToString(m_DroppedLabels) << std::endl;
  os << indent << "LabelChannels: " << (m_LabelChannels ? "On" : "Off") << std::endl;
  os << indent << "MaterialChannels: " << (m_MaterialChannels ? "On" : "Off") << std::endl;
  os << indent << "ChannelLabels: " << DRRLabelSelection::ToString(m_ChannelLabels) << std::endl;
}
} // namespace itk

#endif
