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
#ifndef pbdrrVolumeLoader_h
#define pbdrrVolumeLoader_h

#include "itkImage.h"

#include <functional>
#include <string>
#include <vector>

namespace pbdrr
{
/** A volume of any values: mu, or HU that an int16 cannot hold (4 bytes per voxel). */
using VolumeType = itk::Image<float, 3>;
/** A CT as scanners store it, HU in int16 (2 bytes per voxel): what the filters read in place. */
using HUVolumeType = itk::Image<int16_t, 3>;

/** A volume read for rendering, with what the user should be told about it. It holds the volume in one of two pixel
 * types: int16 HU (2 bytes per voxel, what the filters read in place) when the file says every value is an integer an
 * int16 holds (DICOM: its stored bits, slope and intercept; other files: an 8- or 16-bit signed or 8-bit unsigned pixel
 * type), float for any other. The volume is reached only through Visit() (in its own type), AsFloat() (as float,
 * whatever it was read as) or Grid(): no field a caller can read as null. */
class LoadedVolume
{
public:
  /** Holds volume, read as int16 HU, or as float (not null). */
  void
  Set(HUVolumeType::Pointer volume);
  void
  Set(VolumeType::Pointer volume);

  /** True once Set(): a loader that returns a LoadedVolume has set it. */
  bool
  IsSet() const
  {
    return m_HU || m_Image;
  }

  /** True if the volume is held as int16 HU. */
  bool
  HoldsHU() const
  {
    return m_HU.IsNotNull();
  }

  /** Calls visit with the volume in its own type (HUVolumeType * or VolumeType *) and returns what it returns: the
   * templated filters take either. Throws std::logic_error if no volume is held. */
  template <typename TVisitor>
  decltype(auto)
  Visit(TVisitor && visit) const
  {
    if (m_HU)
    {
      return visit(m_HU.GetPointer());
    }
    if (!m_Image)
    {
      ThrowNotSet();
    }
    return visit(m_Image.GetPointer());
  }

  /** The volume as float values: the one held, or a float copy of the int16 one (4 bytes per voxel). Never null. */
  VolumeType::Pointer
  AsFloat() const;

  /** The volume, whichever its pixel type: its grid. Never null once set. */
  const itk::ImageBase<3> *
  Grid() const;

  std::string              Description; // where it came from: file, or DICOM series and its slices
  std::vector<std::string> Notes;       // e.g. "3 series in DIR; using ..."
  /** The reader of a streamed volume (`--stream`), kept alive: an image holds only a weak pointer to its source, and
   * the filter requests the volume from it slab by slab. Null for a volume read whole. */
  itk::ProcessObject::Pointer Source;

private:
  [[noreturn]] static void
  ThrowNotSet();

  HUVolumeType::Pointer m_HU;
  VolumeType::Pointer   m_Image;
};

/** Told how many files of a DICOM series have been read, of how many, while they are read (for a progress line): by the
 * threads that read them, one call at a time. */
using LoadProgress = std::function<void(size_t filesRead, size_t files)>;

/** Reads INPUT: a DICOM series directory (series discovery through GDCM; the largest series unless seriesUID) or
 * any 3D scalar volume ITK reads. A DICOM series is checked before it is read: one orientation, slice positions
 * along the slice normal (no gantry tilt), no missing slices and even spacing; each violation throws
 * std::runtime_error with the reason, as does a missing path, a 2D, 4D or vector image. */
LoadedVolume
LoadVolume(const std::string & input, const std::string & seriesUID, const LoadProgress & progress = {});

/** `pbdrr --list-series ROOT`: the DICOM series in ROOT and the folders below it, a line each (kind, modality, size,
 * tilt, description, UID, folder), then what was skipped. Throws std::runtime_error if ROOT is not a directory or
 * holds no series. */
std::string
ListDicomSeries(const std::string & root);
} // namespace pbdrr

#endif
