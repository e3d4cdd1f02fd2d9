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
#ifndef itkDRRLabelSelection_h
#define itkDRRLabelSelection_h

#include "itkDRRAttenuationVolume.h"
#include "PointBasedDRRExport.h"

#include <cstdint>
#include <vector>

namespace itk
{
/** \class DRRLabelSelection
 * \brief Which voxels of a labelled volume attenuate, and which channel each one adds to (docs/design.md section 13).
 *
 * A label image on the volume's grid gives every voxel a label (0 to 65535). The kept labels (none listed: every
 * label) minus the dropped ones attenuate; the other voxels become air in the attenuation volume
 * (DRRAttenuationVolume::ApplyVoxelMask()). With channels, every attenuating label present is one channel, in
 * increasing label order (DRRAttenuationVolume::SetVoxelChannels()), so that one render gives a line-integral image
 * per label whose sum is the image of the kept labels.
 *
 * A kept or dropped label that no voxel has is an error: it is a typo far more often than an intent.
 *
 * \sa DRRImageFilterBase::SetLabelImage()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRLabelSelection
{
public:
  /** A label value. */
  using LabelType = uint16_t;
  /** A list of labels. */
  using LabelListType = std::vector<LabelType>;

  /** Most channels one render holds (DRRPointRenderer::Settings::NumberOfChannels). */
  static constexpr unsigned int MaximumNumberOfChannels = 256;

  /** Applies the selection to a volume built from the same grid (labels: one per voxel, x fastest): masks the voxels
   * of labels left out and, with channels, gives every voxel its channel. Returns the labels of the channels in
   * channel order (empty without channels). Throws for a kept or dropped label no voxel has, for a selection that
   * leaves no label, and for more than MaximumNumberOfChannels channels. */
  static LabelListType
  Apply(const LabelType *      labels,
        const LabelListType &  keptLabels,
        const LabelListType &  droppedLabels,
        bool                   channels,
        DRRAttenuationVolume & volume,
        MultiThreaderBase *    threader);

  /** A flag per label value (0 to 65535): 1 if some voxel has it. */
  using LabelFlagsType = std::vector<uint8_t>;

  /** The labels present in volume's voxels (labels: one per voxel of its grid, x fastest), in parallel over its fixed
   * blocks. */
  static LabelFlagsType
  FindPresent(const LabelType * labels, const DRRAttenuationVolume & volume, MultiThreaderBase * threader);
  /** The same for numberOfVoxels labels of no model (the whole label image, for a slab's channels). */
  static LabelFlagsType
  FindPresent(const LabelType * labels, uint64_t numberOfVoxels, MultiThreaderBase * threader);

  /** Throws for a kept or dropped label not present, and for a selection that leaves no label present. Returns the
   * labels that attenuate, in increasing order. */
  static LabelListType
  Verify(const LabelFlagsType & present, const LabelListType & keptLabels, const LabelListType & droppedLabels);

  /** Apply() without its checks, for a slab of the volume whose labels are not all the volume's (present: the slab's;
   * the stage checks the union of the slabs'): masks the voxels of labels left out, every voxel when none is left. */
  static void
  ApplyToSlab(const LabelType *      labels,
              const LabelFlagsType & present,
              const LabelListType &  keptLabels,
              const LabelListType &  droppedLabels,
              DRRAttenuationVolume & volume,
              MultiThreaderBase *    threader);

  /** ApplyToSlab() with channels: gives every voxel of the slab the channel of its label in channelLabels, the whole
   * volume's (Verify() of the labels present in the whole volume), so that every slab numbers the channels alike, as
   * Apply() numbers them on the whole volume. Throws for more than MaximumNumberOfChannels channels. */
  static void
  ApplyChannelsToSlab(const LabelType *      labels,
                      const LabelFlagsType & present,
                      const LabelListType &  channelLabels,
                      const LabelListType &  keptLabels,
                      const LabelListType &  droppedLabels,
                      DRRAttenuationVolume & volume,
                      MultiThreaderBase *    threader);

  /** "1, 3, 7": a list of labels for messages and metadata. */
  static std::string
  ToString(const LabelListType & labels);
};
} // namespace itk

#endif
