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
#ifndef itkDRRImageToAttenuationVolumeFilter_hxx
#define itkDRRImageToAttenuationVolumeFilter_hxx

#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkDRRMaterialTable.h"
#include "itkNearestNeighborInterpolateImageFunction.h"
#include "itkResampleImageFilter.h"

#include <algorithm>
#include <cmath>

namespace itk
{
template <typename TInputImage>
DRRImageToAttenuationVolumeFilter<TInputImage>::DRRImageToAttenuationVolumeFilter()
  : m_TransferFunction(TransferFunctionType::New())
{
  this->SetNumberOfRequiredInputs(1);
  this->SetNumberOfRequiredOutputs(1);
  this->SetNthOutput(0, this->MakeOutput(0));
}

template <typename TInputImage>
DataObject::Pointer
DRRImageToAttenuationVolumeFilter<TInputImage>::MakeOutput(DataObjectPointerArraySizeType)
{
  return OutputType::New().GetPointer();
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::SetInput(const InputImageType * input)
{
  this->SetNthInput(0, const_cast<InputImageType *>(input));
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::GetInput() const -> const InputImageType *
{
  return itkDynamicCastInDebugMode<const InputImageType *>(this->GetPrimaryInput());
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::GetOutput() -> OutputType *
{
  return static_cast<OutputType *>(this->GetPrimaryOutput());
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::GetOutput() const -> const OutputType *
{
  return static_cast<const OutputType *>(this->GetPrimaryOutput());
}

template <typename TInputImage>
ModifiedTimeType
DRRImageToAttenuationVolumeFilter<TInputImage>::GetMTime() const
{
  ModifiedTimeType latest = Superclass::GetMTime();
  if (m_TransferFunction)
  {
    latest = std::max(latest, m_TransferFunction->GetMTime());
  }
  return latest;
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion(); // every input's largest possible region
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (!m_TransferFunction)
  {
    itkExceptionMacro("no transfer function set");
  }
  if (m_MaterialChannels)
  {
    if (m_TransferFunction->GetMode() != DRRTransferFunction::ModeEnum::Materials ||
        !m_TransferFunction->GetMaterialTable())
    {
      itkExceptionMacro("material channels need the transfer function's Materials mode (SetMaterialTable())");
    }
    if (m_LabelChannels)
    {
      itkExceptionMacro("material channels and label channels cannot be rendered together");
    }
    const unsigned int K = m_TransferFunction->GetMaterialTable()->GetNumberOfMaterials();
    if (K > DRRLabelSelection::MaximumNumberOfChannels)
    {
      itkExceptionMacro("" << K << " materials are more channels than a render holds ("
                           << DRRLabelSelection::MaximumNumberOfChannels << ")");
    }
  }
  if (!this->GetLabelImage() && (!m_KeptLabels.empty() || !m_DroppedLabels.empty() || m_LabelChannels))
  {
    itkExceptionMacro("kept or dropped labels and label channels need a label image (SetLabelImage())");
  }
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::GenerateData()
{
  const InputImageType * input = this->GetInput();
  const auto             region = input->GetLargestPossibleRegion();
  if (region.GetNumberOfPixels() == 0)
  {
    itkExceptionMacro("the input volume is empty (size " << region.GetSize() << ")");
  }
  if (input->GetBufferedRegion() != region)
  {
    itkExceptionMacro("the whole input volume must be buffered (buffered " << input->GetBufferedRegion() << ", largest "
                                                                           << region << ")");
  }
  OutputType *         volume = this->GetOutput();
  OutputType::SizeType size;
  for (unsigned int a = 0; a < 3; ++a)
  {
    size[a] = region.GetSize()[a];
  }
  SetIndexToPhysical(*input, input->GetLargestPossibleRegion().GetIndex(), *volume);
  // On the filter's threads, as many as its work units.
  MultiThreaderBase * threader = this->GetMultiThreader();
  threader->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  // The pixel container keeps the values alive: 16-bit CT is read in place, not copied.
  volume->Build(input->GetBufferPointer(), size, *m_TransferFunction, threader, input->GetPixelContainer());
  this->ApplyMaterials(*input, *volume);
  this->ApplyLabels(*input, *volume);
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::SetIndexToPhysical(
  const InputImageType &                     input,
  const typename InputImageType::IndexType & firstVoxel,
  OutputType &                               volume)
{
  OutputType::MatrixType indexToPhysical;
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 3; ++c)
    {
      indexToPhysical[r][c] = input.GetDirection()[r][c] * input.GetSpacing()[c];
    }
  }
  typename InputImageType::PointType firstPoint;
  input.TransformIndexToPhysicalPoint(firstVoxel, firstPoint);
  OutputType::PointType origin;
  for (unsigned int r = 0; r < 3; ++r)
  {
    origin[r] = firstPoint[r];
  }
  volume.SetIndexToPhysical(indexToPhysical, origin);
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::ApplyMaterials(const InputImageType & input, OutputType & volume)
{
  if (!m_MaterialChannels)
  {
    return;
  }
  const unsigned int K = m_TransferFunction->GetMaterialTable()->GetNumberOfMaterials();
  LabelListType      channelLabels;
  for (unsigned int m = 0; m < K; ++m)
  {
    channelLabels.push_back(static_cast<LabelPixelType>(m));
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
    OutputType::ParallelizeBlocks(
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
  volume.SetChannelLabels(std::move(channelLabels));
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::ApplyLabels(const InputImageType & input, OutputType & volume)
{
  if (!this->GetLabelImage())
  {
    return;
  }
  const typename LabelImageType::ConstPointer labels = this->LabelsOnVolumeGrid(input);
  const LabelListType                         channelLabels = DRRLabelSelection::Apply(
    labels->GetBufferPointer(), m_KeptLabels, m_DroppedLabels, m_LabelChannels, volume, this->GetMultiThreader());
  if (m_LabelChannels)
  {
    volume.SetChannelLabels(channelLabels);
  }
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::LabelsOnVolumeGrid(const InputImageType & input) const ->
  typename LabelImageType::ConstPointer
{
  const LabelImageType * labels = this->GetLabelImage();
  const auto             region = input.GetLargestPossibleRegion();
  const auto             labelRegion = labels->GetLargestPossibleRegion();
  if (labels->GetBufferedRegion() != labelRegion)
  {
    itkExceptionMacro("the whole label image must be buffered");
  }
  const double tolerance = 1e-4 * input.GetSpacing().GetVnlVector().min_value();
  const bool   sameGrid =
    region.GetSize() == labelRegion.GetSize() &&
    input.GetOrigin().EuclideanDistanceTo(labels->GetOrigin()) <= tolerance &&
    (input.GetSpacing() - labels->GetSpacing()).GetNorm() <= tolerance &&
    (input.GetDirection().GetVnlMatrix() - labels->GetDirection().GetVnlMatrix()).absolute_value_max() <= 1e-6;
  if (sameGrid)
  {
    return labels;
  }
  this->VerifyLabelsCoverVolume(input, *labels);
  itkWarningMacro("the label image (size "
                  << labelRegion.GetSize() << ", spacing " << labels->GetSpacing() << ", origin " << labels->GetOrigin()
                  << ") is not on the volume's grid (size " << region.GetSize() << ", spacing " << input.GetSpacing()
                  << ", origin " << input.GetOrigin()
                  << "): resampled onto it by nearest neighbour, label 0 outside it");
  using ResampleType = ResampleImageFilter<LabelImageType, LabelImageType>;
  auto resample = ResampleType::New();
  resample->SetInput(labels);
  resample->SetInterpolator(NearestNeighborInterpolateImageFunction<LabelImageType, double>::New());
  resample->SetOutputParametersFromImage(&input);
  resample->SetDefaultPixelValue(0);
  resample->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  resample->Update();
  return resample->GetOutput();
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::VerifyLabelsCoverVolume(const InputImageType & input,
                                                                        const LabelImageType & labels) const
{
  // The label indices of the volume's corner voxel centres bound those of every voxel centre (the map is affine).
  const auto                 region = input.GetLargestPossibleRegion();
  const auto                 labelRegion = labels.GetLargestPossibleRegion();
  ContinuousIndex<double, 3> lowest, highest;
  lowest.Fill(NumericTraits<double>::max());
  highest.Fill(NumericTraits<double>::NonpositiveMin());
  for (unsigned int corner = 0; corner < 8; ++corner)
  {
    typename InputImageType::IndexType index = region.GetIndex();
    for (unsigned int a = 0; a < 3; ++a)
    {
      index[a] += (corner >> a & 1u) ? static_cast<IndexValueType>(region.GetSize()[a]) - 1 : 0;
    }
    typename InputImageType::PointType point;
    input.TransformIndexToPhysicalPoint(index, point);
    const auto labelIndex = labels.template TransformPhysicalPointToContinuousIndex<double, double>(point);
    for (unsigned int a = 0; a < 3; ++a)
    {
      lowest[a] = std::min(lowest[a], labelIndex[a]);
      highest[a] = std::max(highest[a], labelIndex[a]);
    }
  }
  for (unsigned int a = 0; a < 3; ++a)
  {
    const double first = static_cast<double>(labelRegion.GetIndex()[a]) - 0.5;
    const double last = first + static_cast<double>(labelRegion.GetSize()[a]);
    if (highest[a] < first || lowest[a] >= last)
    {
      itkExceptionMacro("the label image (size " << labelRegion.GetSize() << ", origin " << labels.GetOrigin()
                                                 << ") covers no voxel of the volume: it belongs to another volume");
    }
  }
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "TransferFunction:" << std::endl;
  m_TransferFunction->Print(os, indent.GetNextIndent());
  os << indent << "LabelImage: " << (this->GetLabelImage() ? "set" : "(none)") << std::endl;
  os << indent << "KeptLabels: " << DRRLabelSelection::ToString(m_KeptLabels) << std::endl;
  os << indent << "DroppedLabels: " << DRRLabelSelection::ToString(m_DroppedLabels) << std::endl;
  os << indent << "LabelChannels: " << (m_LabelChannels ? "On" : "Off") << std::endl;
  os << indent << "MaterialChannels: " << (m_MaterialChannels ? "On" : "Off") << std::endl;
}
} // namespace itk

#endif
