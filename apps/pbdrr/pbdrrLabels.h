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
#ifndef pbdrrLabels_h
#define pbdrrLabels_h

#include "pbdrrApplication.h"

#include <string>

namespace pbdrr
{
/** The label image of --labels FILE: a 3D image of integers from 0 to 65535 (any integer pixel type). Throws
 * UsageError naming the file for a missing or unreadable file, a non-integer or multi-component pixel type, another
 * dimension, or a label out of range. */
BaseFilterType<VolumeType>::LabelImageType::Pointer
ReadLabelImage(const std::string & path);

/** Gives the filter the label options (--labels, --keep-labels, --drop-labels, --label-channels); checks, before any
 * load, that they go together. Nothing without --labels. Instantiated for HUVolumeType and VolumeType. */
template <typename TVolume>
void
ApplyLabelOptions(const Options & options, BaseFilterType<TVolume> * filter);

/** Refuses label options that cannot hold (before anything is loaded or written). */
void
CheckLabelOptions(const Options & options);

/** Writes the channel images of the last render to options.labelChannelsOutput (a multi-component float image, one
 * component per label; the labels in the header key PBDRR_ChannelLabels), through a temporary name. */
template <typename TVolume>
void
WriteLabelChannels(const Options & options, BaseFilterType<TVolume> * filter);
} // namespace pbdrr

#endif
