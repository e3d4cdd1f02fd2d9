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
#ifndef pbdrrBenchmarkVolumes_h
#define pbdrrBenchmarkVolumes_h
// The volumes and images PointBasedDRRBenchmark derives from its input: the centre, mu with an identity direction,
// padded and resampled volumes, crops, and the images it saves.
#include "pbdrrBenchmarkSupport.h"
#include "pbdrrVolumeLoader.h"

#include "itkDRRTransferFunction.h"
#include "itkImageFileWriter.h"

#include <cstdint>
#include <string>

namespace pbdrr
{
namespace bench
{
/** The same voxels at the same physical places with an identity direction matrix, for programs that ignore the
 * direction (ITK's ray caster; plastimatch is given the same). Only for axis-aligned directions (a signed
 * permutation): returns null otherwise. */
MuImageType::Pointer
WithIdentityDirection(const MuImageType * image);

/** Voxels with mu > 0 under the filter's transfer function, counted on the input (the attenuation volume may not hold
 * mu at all: level samplers never ask for it). */
uint64_t
CountNonAir(const VolumeType * volume, const itk::DRRTransferFunction * transfer);

/** The volume with one layer of zero voxels all around (same physical voxel positions). */
MuImageType::Pointer
PadWithZeros(const MuImageType * image);

/** The volume resampled (nearest neighbour, so HU stay integers) to about `fraction` of its voxels over the same
 * box: size per axis scaled by fraction^(1/3). */
VolumeType::Pointer
ResampleToFraction(const VolumeType * volume, double fraction);

/** The columns [c0, c0 + cols) and rows [r0, r0 + rows) of an image `width` columns wide. */
Image
Crop(const Image & image, unsigned width, unsigned c0, unsigned r0, unsigned cols, unsigned rows);

template <typename TImage>
void
Write(const TImage * image, const std::string & path)
{
  auto writer = itk::ImageFileWriter<TImage>::New();
  writer->SetInput(image);
  writer->SetFileName(path);
  writer->Update();
}

void
WriteProjection(const Image & values, unsigned cols, unsigned rows, double spacing, const std::string & path);
} // namespace bench
} // namespace pbdrr

#endif
