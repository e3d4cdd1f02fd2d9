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
#ifndef pbdrrDicomSeriesTree_h
#define pbdrrDicomSeriesTree_h

#include "pbdrrDicomSeriesDiscovery.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** A series found in an export tree, with what a user chooses it by. */
struct DicomSeriesSummary
{
  DicomSeries Series;
  std::string Directory;          // the folder that holds its files
  std::string Description;        // Series Description (0008,103E), trimmed; may be empty
  std::string Modality;           // (0008,0060), e.g. CT
  std::string ImageType;          // (0008,0008), e.g. ORIGINAL\PRIMARY\LOCALIZER
  std::string Size{ "?" };        // "rows x columns x slices" (slices: files, or the frames of one file)
  std::string Tilt;               // Gantry/Detector Tilt (0018,1120) in degrees as stored; empty if absent
  bool        Localizer{ false }; // a scout (surview, topogram): ImageType says LOCALIZER, never a volume
  bool        Volume{ false };    // a CT of two or more slices, or one multi-frame file, that is not a localizer
};

/** Every DICOM series in `root` and the folders below it (GDCM's series discovery in each folder, DICOMDIRs and other
 * non-image objects left out), folders in name order. Folders that cannot be read as series (damaged files, no
 * series) are named in `notes`, not refused: a listing shows what is there. */
std::vector<DicomSeriesSummary>
FindDicomSeriesTree(const std::string & root, std::vector<std::string> & notes);

/** The series to render from a tree: `seriesUID` if given (refused, listing the UIDs, if absent), else the volume of
 * most files (localizers are never chosen); refused if there is none. Says which in `notes` when there was a choice. */
const DicomSeriesSummary &
SelectDicomVolume(const std::vector<DicomSeriesSummary> & series,
                  const std::string &                     seriesUID,
                  const std::string &                     root,
                  std::vector<std::string> &              notes);

/** The listing of `pbdrr --list-series`: a header line and one line per series. */
std::string
FormatDicomSeriesTable(const std::vector<DicomSeriesSummary> & series);
} // namespace pbdrr

#endif
