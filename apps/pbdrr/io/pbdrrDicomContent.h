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
#ifndef pbdrrDicomContent_h
#define pbdrrDicomContent_h

#include "pbdrrGdcmWarningCapture.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** What a file holds, as far as reading a volume goes: for the files of a directory that no series took, and for
 * naming the damaged files of a series. */
enum class DicomContent
{
  NotDicom,
  Damaged,   // starts as DICOM, but GDCM cannot parse it, or its pixel data is cut short
  NoImage,   // a DICOM object without pixel data: a report, a structure set, ...
  Directory, // a media storage directory (DICOMDIR, or a scanner's DIRFILE): an index of other files, no image
  Image
};

/** The SOP class of a media storage directory (DICOMDIR), as its file meta information names it. */
constexpr const char * MediaStorageDirectorySOPClass = "1.2.840.10008.1.3.10";

/** Reads `file` with GDCM (its output captured) and says what it holds. */
DicomContent
ClassifyDicomFile(const std::string & file);

/** Refuses what GDCM read with complaints about the pixel data (it fills what is missing and carries on), naming the
 * damaged ones among `files`. Does nothing if `warnings` heard no such complaint. */
void
RefuseDamagedPixelData(const GdcmWarningCapture & warnings, const std::vector<std::string> & files);
} // namespace pbdrr

#endif
