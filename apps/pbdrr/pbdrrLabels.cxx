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
#include "pbdrrLabels.h"
#include "pbdrrOutputFiles.h"

#include "itkDRRImageFileIntegrity.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageIOFactory.h"
#include "itkMetaDataObject.h"

#include <algorithm>
#include <sstream>

namespace pbdrr
{
namespace
{
using LabelImageType = BaseFilterType<VolumeType>::LabelImageType;
using LabelPixelType = BaseFilterType<VolumeType>::LabelPixelType;

/** A label file of signed or wide integers, read in its own type TFile (a byte per voxel for int8 labels, not the
 * eight of a 64-bit read), each value checked to be a label (0 to 65535) and copied to a label image. */
template <typename TFile>
LabelImageType::Pointer
LabelsFrom(const std::string & path)
{
  const auto file = itk::ReadImage<itk::Image<TFile, 3>>(path);
  auto       labels = LabelImageType::New();
  labels->CopyInformation(file);
  labels->SetRegions(file->GetLargestPossibleRegion());
  labels->Allocate();
  const size_t  n = file->GetBufferedRegion().GetNumberOfPixels();
  const TFile * in = file->GetBufferPointer();
  for (size_t v = 0; v < n; ++v)
  {
    const int64_t value = static_cast<int64_t>(in[v]);
    if (value < 0 || value > 65535)
    {
      throw UsageError("--labels: voxel " + std::to_string(v) + " of " + path + " has label " + std::to_string(value) +
                       "; labels are 0 to 65535");
    }
    labels->GetBufferPointer()[v] = static_cast<LabelPixelType>(value);
  }
  return labels;
}
} // namespace

BaseFilterType<VolumeType>::LabelImageType::Pointer
ReadLabelImage(const std::string & path)
{
  const itk::ImageIOBase::Pointer io =
    itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
  if (!io)
  {
    throw UsageError("--labels: cannot read " + path + " (missing, or not an image ITK reads)");
  }
  const std::string damage = itk::DRRImageFileIntegrity::FindDamage(path);
  if (!damage.empty())
  {
    throw std::runtime_error("--labels: cannot read " + path + ": " + damage);
  }
  io->SetFileName(path);
  io->ReadImageInformation();
  using Component = itk::IOComponentEnum;
  const Component type = io->GetComponentType();
  const bool      integer = type == Component::UCHAR || type == Component::CHAR || type == Component::USHORT ||
                       type == Component::SHORT || type == Component::UINT || type == Component::INT ||
                       type == Component::ULONG || type == Component::LONG || type == Component::ULONGLONG ||
                       type == Component::LONGLONG;
  if (!integer || io->GetNumberOfComponents() != 1)
  {
    throw UsageError("--labels: " + path + " holds " + std::to_string(io->GetNumberOfComponents()) + " x " +
                     itk::ImageIOBase::GetComponentTypeAsString(type) +
                     " per voxel; a label image holds one integer per voxel");
  }
  if (io->GetNumberOfDimensions() != 3)
  {
    throw UsageError("--labels: " + path + " is " + std::to_string(io->GetNumberOfDimensions()) +
                     "D; a label image is 3D, on the CT's grid");
  }
  switch (type)
  {
    case Component::UCHAR:
    case Component::USHORT:
      return itk::ReadImage<LabelImageType>(path); // every value a label: widened by the reader, no check
    case Component::CHAR:
      return LabelsFrom<int8_t>(path);
    case Component::SHORT:
      return LabelsFrom<int16_t>(path);
    case Component::UINT:
      return LabelsFrom<uint32_t>(path);
    case Component::INT:
      return LabelsFrom<int32_t>(path);
    default:
      return LabelsFrom<int64_t>(path); // 64-bit labels (a value beyond 2^63 reads negative, and is refused)
  }
}

void
CheckLabelOptions(const Options & options)
{
  if (options.jensenCorrection && !IsPolychromatic(options))
  {
    throw UsageError("--jensen-correction corrects a polychromatic image (--spectrum or --kvp)");
  }
  if (!options.materialsFile.empty() && !IsPolychromatic(options))
  {
    throw UsageError("--materials is the material table of a polychromatic beam (--spectrum or --kvp)");
  }
  const bool selection = !options.keepLabels.empty() || !options.dropLabels.empty();
  if ((selection || !options.labelChannelsOutput.empty()) && options.labelsFile.empty())
  {
    throw UsageError("--keep-labels, --drop-labels and --label-channels need a label image (--labels FILE)");
  }
  if (!options.labelChannelsOutput.empty())
  {
    if (OutputKind(options.labelChannelsOutput) == "png")
    {
      throw UsageError("--label-channels needs a float format of many components (.mha, .nrrd, .nii), not .png");
    }
    if (!options.exact && options.controlVariateGiven && options.controlVariate != 0 &&
        options.controlVariate != itk::DRRControlVariate::AutomaticFactor)
    {
      throw UsageError("--label-channels renders without a control variate (its coarse blocks mix labels): drop "
                       "--control-variate");
    }
    CheckWritable(options.labelChannelsOutput);
  }
}

template <typename TVolume>
void
ApplyLabelOptions(const Options & options, BaseFilterType<TVolume> * filter)
{
  if (options.labelsFile.empty())
  {
    return;
  }
  filter->SetLabelImage(ReadLabelImage(options.labelsFile));
  filter->SetKeptLabels(options.keepLabels);
  filter->SetDroppedLabels(options.dropLabels);
  filter->SetLabelChannels(!options.labelChannelsOutput.empty());
}

template <typename TVolume>
void
WriteLabelChannels(const Options & options, BaseFilterType<TVolume> * filter)
{
  if (options.labelChannelsOutput.empty())
  {
    return;
  }
  auto * channels = filter->GetChannelOutput();
  itk::EncapsulateMetaData<std::string>(channels->GetMetaDataDictionary(),
                                        "PBDRR_ChannelLabels",
                                        itk::DRRLabelSelection::ToString(filter->GetChannelLabels()));
  WriteAtomically(options.labelChannelsOutput, [&](const std::string & temporary) {
    auto writer = itk::ImageFileWriter<typename BaseFilterType<TVolume>::ChannelImageType>::New();
    writer->SetInput(channels);
    writer->SetFileName(temporary);
    writer->Update();
  });
}

template void
ApplyLabelOptions(const Options &, BaseFilterType<HUVolumeType> *);
template void
ApplyLabelOptions(const Options &, BaseFilterType<VolumeType> *);
template void
WriteLabelChannels(const Options &, BaseFilterType<HUVolumeType> *);
template void
WriteLabelChannels(const Options &, BaseFilterType<VolumeType> *);
} // namespace pbdrr
