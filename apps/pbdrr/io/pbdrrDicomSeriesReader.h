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
#ifndef pbdrrDicomSeriesReader_h
#define pbdrrDicomSeriesReader_h

#include "pbdrrVolumeLoader.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** Reads the slices `files` (one series, in order, two or more) as a volume, after checking from their headers that
 * they form one regular grid (CheckSliceStack); the third spacing is the slices' own, not GDCM's. Refused, with
 * std::runtime_error, if they do not or if GDCM finds their pixel data damaged. `notDicom` (the files of `directory`
 * that are not DICOM) are named beside a refusal of the slices: a slice cut to a few bytes is one of them. `progress`
 * (may be empty) is told the files read as the reader goes. The volume is held as int16 HU (2 bytes per voxel)
 * when every slice's stored bits, slope and intercept give integers an int16 holds, else as float (LoadedVolume::Set).
 */
void
ReadDicomSeries(const std::vector<std::string> & files,
                const std::vector<std::string> & notDicom,
                const std::string &              directory,
                LoadedVolume &                   loaded,
                const LoadProgress &             progress = {});
} // namespace pbdrr

#endif
