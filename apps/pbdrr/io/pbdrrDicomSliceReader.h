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
#ifndef pbdrrDicomSliceReader_h
#define pbdrrDicomSliceReader_h

#include "pbdrrVolumeLoader.h"

#include "itkMultiThreaderBase.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** Reads the DICOM slices `files` (in this order, two or more) into one volume: the volume itk::ImageSeriesReader
 * with a GDCMImageIO reads from them, bit for bit (its origin, spacing and direction, forceOrthogonalDirection being
 * that reader's flag of the same name, and its values), with the files decoded on the threads of `threader` (a
 * threader of its own, with ITK's default number of threads, if null), each straight into its slice of the volume.
 * `progress` (may be empty) is told how many files have been read, by one thread at a time.
 *
 * It reads the common case only: every file one 2D frame of the first file's size, one MONOCHROME2 sample per pixel
 * of 8, 16 or 32 bits, stored uncompressed or as JPEG 2000. For any other file (MONOCHROME1, which GDCMImageIO
 * inverts, colour, several frames, other compression), or any error, it returns null: ImageSeriesReader then reads
 * them, with its own conversions, warnings and error messages. */
template <typename TVolume>
typename TVolume::Pointer
ReadDicomSlices(const std::vector<std::string> & files,
                bool                             forceOrthogonalDirection,
                const LoadProgress &             progress = {},
                itk::MultiThreaderBase *         threader = nullptr);
} // namespace pbdrr

#endif
