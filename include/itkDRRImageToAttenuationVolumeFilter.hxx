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
#include <functional>

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
DRRImageToAttenuationVolumeFilter<TInputImage>::GenerateOutputInformation()
{
  if (const InputImageType * input = this->GetInput())
  {
    this->GetOutput()->SetLargestPossibleRegion(input->GetLargestPossibleRegion());
  }
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion(); // every input's largest possible region
  this->VerifyInputFile();
  auto * input = const_cast<InputImageType *>(this->GetInput());
  if (!input)
  {
    return;
  }
  RegionType region = this->GetOutput()->GetRequestedRegion();
  if (region.GetNumberOfPixels() == 0)
  {
    region = input->GetLargestPossibleRegion(); // not asked through the model's pipeline: the whole volume
  }
  if (input->GetSource() && !input->GetBufferedRegion().IsInside(region))
  {
    // The source makes the region anew: free the last one first, or the reader allocates the slab beside it. The
    // last model, which may read it in place, is freed before the source runs (PrepareOutputs()).
    input->ReleaseData();
  }
  input->SetRequestedRegion(region);
  if (auto * labels = const_cast<LabelImageType *>(this->GetLabelImage()))
  {
    // Label channels are numbered by the labels of the whole volume: a slab of them reads the whole label image.
    labels->SetRequestedRegion(m_LabelChannels ? labels->GetLargestPossibleRegion()
                                               : LabelRegionOf(*input, *labels, region));
  }
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::VerifyInputFile()
{
  const InputImageType * input = this->GetInput();
  const std::string      file = input ? DRRImageFileIntegrity::GetSourceFileName(input) : std::string();
  if (file.empty())
  {
    return;
  }
  const ModifiedTimeType readerTime = input->GetSource()->GetMTime();
  if (file != m_CheckedInputFile || readerTime != m_CheckedInputFileTime)
  {
    DRRImageFileIntegrity::Check(file);
    m_CheckedInputFile = file;
    m_CheckedInputFileTime = readerTime;
  }
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::LabelRegionOf(const InputImageType & input,
                                                              const LabelImageType & labels,
                                                              const RegionType &     region) ->
  typename LabelImageType::RegionType
{
  const auto largest = input.GetLargestPossibleRegion();
  const auto labelLargest = labels.GetLargestPossibleRegion();
  if (!IsOnVolumeGrid(input, labels))
  {
    return labelLargest;
  }
  typename LabelImageType::RegionType matching(region.GetSize());
  for (unsigned int a = 0; a < 3; ++a)
  {
    matching.SetIndex(a, region.GetIndex()[a] - largest.GetIndex()[a] + labelLargest.GetIndex()[a]);
  }
  return matching;
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
  const auto             largest = input->GetLargestPossibleRegion();
  if (largest.GetNumberOfPixels() == 0)
  {
    itkExceptionMacro("the input volume is empty (size " << largest.GetSize() << ")");
  }
  OutputType * volume = this->GetOutput();
  RegionType   region = volume->GetRequestedRegion();
  if (region.GetNumberOfPixels() == 0)
  {
    region = largest;
  }
  const auto * values = this->GetRegionValues(*input, region);
  SetIndexToPhysical(*input, region.GetIndex(), *volume);
  // On the filter's threads, as many as its work units.
  MultiThreaderBase * threader = this->GetMultiThreader();
  threader->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  // The pixel container keeps the values alive: 16-bit CT is read in place, not copied.
  volume->Build(values,
                { { region.GetSize()[0], region.GetSize()[1], region.GetSize()[2] } },
                *m_TransferFunction,
                threader,
                input->GetPixelContainer());
  this->ApplyMaterials(values, *volume);
  this->ApplyLabels(*input, region, *volume);
  volume->SetBufferedRegion(region);
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::GetRegionValues(const InputImageType & input,
                                                                const RegionType &     region) const
  -> const InputPixelType *
{
  const auto largest = input.GetLargestPossibleRegion();
  const auto buffered = input.GetBufferedRegion();
  const auto wholePlanesOf = [&](const RegionType & r) {
    return r.GetNumberOfPixels() > 0 && largest.IsInside(r) && r.GetSize()[0] == largest.GetSize()[0] &&
           r.GetSize()[1] == largest.GetSize()[1];
  };
  if (!wholePlanesOf(region))
  {
    itkExceptionMacro("the model's requested region " << region << " is not whole z planes of the input volume's "
                                                      << largest);
  }
  if (!wholePlanesOf(buffered) || !buffered.IsInside(region))
  {
    itkExceptionMacro("the input's source gave " << buffered << " for " << region
                                                 << ": the volume must be buffered in whole z planes (largest "
                                                 << largest << ")");
  }
  const size_t plane = static_cast<size_t>(buffered.GetSize()[0]) * buffered.GetSize()[1];
  return input.GetBufferPointer() + plane * static_cast<size_t>(region.GetIndex()[2] - buffered.GetIndex()[2]);
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
DRRImageToAttenuationVolumeFilter<TInputImage>::ApplyMaterials(const InputPixelType * values, OutputType & volume)
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
    std::vector<uint8_t> channels(volume.GetNumberOfVoxels());
    const auto           materialOf = [&](double value) {
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
DRRImageToAttenuationVolumeFilter<TInputImage>::ApplyLabels(const InputImageType & input,
                                                            const RegionType &     region,
                                                            OutputType &           volume)
{
  if (!this->GetLabelImage())
  {
    return;
  }
  const RegionType                            largest = input.GetLargestPossibleRegion();
  const LabelPixelType *                      first = nullptr;
  const typename LabelImageType::ConstPointer labels = this->LabelsOnVolumeGrid(input, region, first);
  if (region != largest && m_LabelChannels)
  {
    this->ApplySlabLabelChannels(input, first, region, volume);
    return;
  }
  if (region != largest)
  {
    this->ApplySlabLabels(first, region, largest, volume);
    return;
  }
  const LabelListType channelLabels =
    DRRLabelSelection::Apply(first, m_KeptLabels, m_DroppedLabels, m_LabelChannels, volume, this->GetMultiThreader());
  if (m_LabelChannels)
  {
    volume.SetChannelLabels(channelLabels);
  }
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::ApplySlabLabels(const LabelPixelType * labels,
                                                                const RegionType &     region,
                                                                const RegionType &     largest,
                                                                OutputType &           volume)
{
  const auto present = DRRLabelSelection::FindPresent(labels, volume, this->GetMultiThreader());
  DRRLabelSelection::ApplyToSlab(labels, present, m_KeptLabels, m_DroppedLabels, volume, this->GetMultiThreader());
  // A kept or dropped label must be in some voxel of the volume: checked on the union of the slabs' labels once the
  // slabs, read in order from the first plane (as the DRR filters read them), reach the last. Slabs read otherwise
  // are not checked.
  const IndexValueType firstPlane = region.GetIndex()[2];
  const IndexValueType endPlane = firstPlane + static_cast<IndexValueType>(region.GetSize()[2]);
  if (firstPlane == largest.GetIndex()[2])
  {
    m_LabelsInSlabs = present;
  }
  else if (firstPlane == m_NextSlabPlane && !m_LabelsInSlabs.empty())
  {
    std::transform(
      m_LabelsInSlabs.begin(), m_LabelsInSlabs.end(), present.begin(), m_LabelsInSlabs.begin(), std::bit_or<uint8_t>());
  }
  else
  {
    m_LabelsInSlabs.clear();
  }
  m_NextSlabPlane = endPlane;
  if (!m_LabelsInSlabs.empty() && endPlane == largest.GetIndex()[2] + static_cast<IndexValueType>(largest.GetSize()[2]))
  {
    DRRLabelSelection::Verify(m_LabelsInSlabs, m_KeptLabels, m_DroppedLabels);
  }
}

template <typename TInputImage>
void
DRRImageToAttenuationVolumeFilter<TInputImage>::ApplySlabLabelChannels(const InputImageType & input,
                                                                       const LabelPixelType * labels,
                                                                       const RegionType &     region,
                                                                       OutputType &           volume)
{
  // The whole volume's labels check the kept and dropped ones (the slab's need not hold them) and number the channels.
  const LabelListType channelLabels = this->GetWholeChannelLabels(input, region.GetSize()[2]);
  const auto          present = DRRLabelSelection::FindPresent(labels, volume, this->GetMultiThreader());
  DRRLabelSelection::ApplyChannelsToSlab(
    labels, present, channelLabels, m_KeptLabels, m_DroppedLabels, volume, this->GetMultiThreader());
  volume.SetChannelLabels(channelLabels);
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::GetWholeChannelLabels(const InputImageType & input,
                                                                      SizeValueType planes) -> const LabelListType &
{
  // The input's own time changes with every slab read: its source's is the one that counts.
  const LabelImageType * labelImage = this->GetLabelImage();
  const auto             timeOf = [](const DataObject & image) {
    return image.GetSource() ? image.GetPipelineMTime() : image.GetMTime();
  };
  const ModifiedTimeType madeOf = std::max({ this->GetMTime(), timeOf(*labelImage), timeOf(input) });
  if (!m_WholeChannelLabels.empty() && madeOf < m_WholeChannelLabelsTime.GetMTime())
  {
    return m_WholeChannelLabels;
  }
  // planes at a time: resampled labels off the volume's grid are never held whole.
  const RegionType                  largest = input.GetLargestPossibleRegion();
  DRRLabelSelection::LabelFlagsType present(size_t{ 1 } << 16, 0);
  for (SizeValueType plane = 0; plane < largest.GetSize()[2]; plane += planes)
  {
    RegionType part = largest;
    part.SetIndex(2, largest.GetIndex()[2] + static_cast<IndexValueType>(plane));
    part.SetSize(2, std::min(planes, largest.GetSize()[2] - plane));
    const LabelPixelType * first = nullptr;
    const auto             labels = this->LabelsOnVolumeGrid(input, part, first, false);
    const auto partPresent = DRRLabelSelection::FindPresent(first, part.GetNumberOfPixels(), this->GetMultiThreader());
    std::transform(present.begin(), present.end(), partPresent.begin(), present.begin(), std::bit_or<uint8_t>());
  }
  m_WholeChannelLabels = DRRLabelSelection::Verify(present, m_KeptLabels, m_DroppedLabels);
  m_WholeChannelLabelsTime.Modified();
  return m_WholeChannelLabels;
}

template <typename TInputImage>
auto
DRRImageToAttenuationVolumeFilter<TInputImage>::LabelsOnVolumeGrid(const InputImageType &  input,
                                                                   const RegionType &      region,
                                                                   const LabelPixelType *& first,
                                                                   bool                    warn) const ->
  typename LabelImageType::ConstPointer
{
  const LabelImageType * labels = this->GetLabelImage();
  const auto             largest = input.GetLargestPossibleRegion();
  const auto             labelRegion = labels->GetLargestPossibleRegion();
  if (IsOnVolumeGrid(input, *labels))
  {
    // The labels of the region's planes, read in place.
    const auto wanted = LabelRegionOf(input, *labels, region);
    const auto buffered = labels->GetBufferedRegion();
    if (!buffered.IsInside(wanted) || buffered.GetSize()[0] != labelRegion.GetSize()[0] ||
        buffered.GetSize()[1] != labelRegion.GetSize()[1])
    {
      itkExceptionMacro("the label image's source gave " << buffered << " for " << wanted
                                                         << ": the labels must be buffered in whole z planes");
    }
    const size_t plane = static_cast<size_t>(buffered.GetSize()[0]) * buffered.GetSize()[1];
    first = labels->GetBufferPointer() + plane * static_cast<size_t>(wanted.GetIndex()[2] - buffered.GetIndex()[2]);
    return labels;
  }
  if (labels->GetBufferedRegion() != labelRegion)
  {
    itkExceptionMacro("the whole label image must be buffered");
  }
  this->VerifyLabelsCoverVolume(input, *labels);
  if (warn && region.GetIndex()[2] == largest.GetIndex()[2])
  {
    // Once per volume, not once per slab.
    itkWarningMacro("the label image (size " << labelRegion.GetSize() << ", spacing " << labels->GetSpacing()
                                             << ", origin " << labels->GetOrigin()
                                             << ") is not on the volume's grid (size " << largest.GetSize()
                                             << ", spacing " << input.GetSpacing() << ", origin " << input.GetOrigin()
                                             << "): resampled onto it by nearest neighbour, label 0 outside it");
  }
  // The region's voxels alone: ResampleImageFilter maps each output row from its first voxel, so a slab's labels are
  // the whole volume's, bit for bit.
  using ResampleType = ResampleImageFilter<LabelImageType, LabelImageType>;
  auto resample = ResampleType::New();
  resample->SetInput(labels);
  resample->SetInterpolator(NearestNeighborInterpolateImageFunction<LabelImageType, double>::New());
  resample->SetOutputParametersFromImage(&input);
  resample->SetOutputStartIndex(region.GetIndex());
  resample->SetSize(region.GetSize());
  resample->SetDefaultPixelValue(0);
  resample->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  resample->Update();
  first = resample->GetOutput()->GetBufferPointer();
  return resample->GetOutput();
}

template <typename TInputImage>
bool
DRRImageToAttenuationVolumeFilter<TInputImage>::IsOnVolumeGrid(const InputImageType & input,
                                                               const LabelImageType & labels)
{
  const double tolerance = 1e-4 * input.GetSpacing().GetVnlVector().min_value();
  return input.GetLargestPossibleRegion().GetSize() == labels.GetLargestPossibleRegion().GetSize() &&
         input.GetOrigin().EuclideanDistanceTo(labels.GetOrigin()) <= tolerance &&
         (input.GetSpacing() - labels.GetSpacing()).GetNorm() <= tolerance &&
         (input.GetDirection().GetVnlMatrix() - labels.GetDirection().GetVnlMatrix()).absolute_value_max() <= 1e-6;
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
