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
#ifndef pbdrrVolumeFileReader_h
#define pbdrrVolumeFileReader_h

#include "pbdrrVolumeLoader.h"

#include "itkImageIOBase.h"

#include <string>

namespace pbdrr
{
/** Refuses, with std::runtime_error naming the file and what is missing, an image file that holds less than its
 * header promises or whose compressed stream is cut or damaged (itk::DRRImageFileIntegrity: MetaImage, NRRD, NIfTI,
 * TIFF), before any reader reads it: ITK's NIfTI and TIFF readers fill what is missing with zeros, and MetaImage's,
 * streamed, reports it on std::cerr only. */
void
RefuseDamagedImageFile(const std::string & path);

/** Reads the image file `path` through `io` (its image information read) as a float volume. Refuses, with
 * std::runtime_error, an image that is not 3D or not scalar, and one the reader reports read short or damaged (some
 * readers, MetaImage's, only say so on std::cerr and carry on); the reader's other messages still reach std::cerr. */
VolumeType::Pointer
ReadVolumeFile(const std::string & path, const itk::ImageIOBase::Pointer & io);

/** The same read as ReadVolumeFile(), into the HU volume of `loaded` when the file's pixel type is one an int16 holds
 * (int8, uint8, int16: read as stored, 2 bytes per voxel), else into its float volume. */
void
ReadVolumeFileInto(const std::string & path, const itk::ImageIOBase::Pointer & io, LoadedVolume & loaded);
} // namespace pbdrr

#endif
