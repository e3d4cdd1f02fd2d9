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
#ifndef pbdrrDicomFileCheck_h
#define pbdrrDicomFileCheck_h

#include <string>

namespace pbdrr
{
/** Checks that a DICOM Part 10 file (128-byte preamble, "DICM") is whole before GDCM reads it: walks its element
 * headers, sequences and pixel-data fragments without reading the values, and reports where a header promises more
 * bytes than the file holds. GDCM, as Debian builds it, aborts the process (a failed assertion) on some files cut
 * short inside their header, and silently zero-fills pixel data cut short; this check runs first.
 *
 * Returns an empty string for a whole file, for a file that is not DICOM Part 10 and for an encoding it does not walk
 * (big endian, deflated, an unknown value representation): those are left to GDCM. Otherwise a description of the
 * damage, e.g. "element (7fe0,0010) needs 524288 bytes at offset 1102, the file ends at 400000". */
std::string
FindDicomTruncation(const std::string & path);

/** Whether the file starts as a DICOM Part 10 file: a 128-byte preamble, then "DICM". */
bool
IsDicomPart10File(const std::string & path);
} // namespace pbdrr

#endif
