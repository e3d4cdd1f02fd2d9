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
#ifndef itkDRRImageFileIntegrity_h
#define itkDRRImageFileIntegrity_h

#include "itkDRRCompatibility.h"
#include "PointBasedDRRExport.h"
#include "itkDataObject.h"

#include <string>

namespace itk
{
/** \class DRRImageFileIntegrity
 * \brief Whether an image file holds every byte its header promises: a cut or damaged file found before it is read.
 *
 * ITK's readers do not all report a short read: NIfTI's (.nii and .nii.gz) and TIFF's fill what is missing with
 * zeros, which a CT reads as water, and MetaImage's, asked for a region (streaming), reports it on std::cerr only and
 * returns the region half read. This check reads the header itself and compares:
 *
 * - MetaImage (.mha, .mhd and its data file): the data's bytes (DimSize, ElementType, ElementNumberOfChannels) after
 *   the header (ElementDataFile = LOCAL) or in the data file; a zlib stream (CompressedData = True) is inflated to its
 *   end.
 * - NRRD (.nrrd, .nhdr and its data file): the same (sizes, type; byte skip and line skip), raw or gzip.
 * - NIfTI-1 and NIfTI-2 (.nii, .nii.gz, .hdr with its .img): the voxels after vox_offset; a gzip stream inflated to
 *   its end, every member.
 * - TIFF and BigTIFF (.tif, .tiff): every directory of the chain, and every strip and tile it names, inside the file.
 *
 * A compressed stream is inflated once (the cost of a read); an uncompressed file costs a stat. Formats it does not
 * know (DICOM, whose own checks are pbdrr's, PNG, ...), and the forms of the ones above whose data it cannot place
 * (a MetaImage LIST of files, an NRRD data file pattern, ASCII encodings) are not checked: their readers report what
 * they miss. A file longer than its header promises is not damage.
 *
 * The DRR filters call it on the file of an itk::ImageFileReader upstream of their input before anything is read,
 * whole or slab by slab (DRRImageFilterBase); a user of another reader calls it on the file.
 *
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRImageFileIntegrity
{
public:
  /** What is wrong with the image file at `path`, in a sentence that names what is missing ("it holds 4096 bytes of
   * pixel data where its header promises 6144: the file is truncated"), or "" for a whole file and for a format this
   * check does not know. A file that cannot be opened is damage ("cannot open it: No such file or directory"). */
  static std::string
  FindDamage(const std::string & path);

  /** Throws an ExceptionObject naming `path` and its damage if FindDamage(path) finds any. */
  static void
  Check(const std::string & path);

  /** The file the source of `data` reads: its "FileName" input (itk::ImageFileReader's), or "" if it has none. */
  static std::string
  GetSourceFileName(const DataObject * data);

  /** True for a file whose format (by its extension) this check knows. */
  static bool
  IsCheckedFormat(const std::string & path);
};
} // namespace itk

#endif
