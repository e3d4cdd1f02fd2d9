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
#ifndef pbdrrDicomMultiFrame_h
#define pbdrrDicomMultiFrame_h

#include "pbdrrVolumeLoader.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** Reads a DICOM file alone as a volume: a multi-frame file (a single slice is refused as 2D). An enhanced file's
 * frames are placed where their per-frame positions say (checked as a series' slices are; frames stored downwards
 * give a third axis pointing down); a legacy file without them is placed by its Spacing Between Slices, if GDCM
 * agrees with its Pixel Spacing, with a note in `notes`. Refused, with std::runtime_error, if GDCM finds its pixel
 * data damaged. */
VolumeType::Pointer
ReadDicomFile(const std::string & file, std::vector<std::string> & notes);
} // namespace pbdrr

#endif
