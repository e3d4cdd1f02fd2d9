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
#ifndef pbdrrDicomSeriesDiscovery_h
#define pbdrrDicomSeriesDiscovery_h

#include <string>
#include <vector>

namespace pbdrr
{
/** A DICOM series as found: its Series Instance UID (empty if its files have none) and its files, in the order GDCM
 * puts its slices. */
struct DicomSeries
{
  std::string              UID;
  std::vector<std::string> Files;
};

/** What a directory holds for pbdrr: its DICOM series, and what else is there. Another place to look (a DICOMDIR, a
 * tree of folders) can fill the same. */
struct DicomSeriesList
{
  std::vector<DicomSeries> Series;   // in the order GDCM found them
  std::vector<std::string> NotDicom; // files of no series that are not DICOM (a slice cut to a few bytes is one)
  std::vector<std::string> Notes;    // DICOM objects of no series, ignored: said to the user
};

/** The DICOM series of `directory` (not its subdirectories), found by GDCM. Refused with std::runtime_error, before
 * GDCM reads any file, if a DICOM file of the directory is truncated or damaged; refused too if a DICOM file no series
 * took cannot be read, or if there is no series. The caller listens to GDCM (a GdcmWarningCapture). */
DicomSeriesList
FindDicomSeries(const std::string & directory);

/** The series `seriesUID` of `list`, or without one the largest (with a note in `notes` if there were several).
 * Refuses an unknown UID, listing those available. `directory` names where they were found in messages. */
const DicomSeries &
SelectDicomSeries(const DicomSeriesList &    list,
                  const std::string &        seriesUID,
                  const std::string &        directory,
                  std::vector<std::string> & notes);
} // namespace pbdrr

#endif
