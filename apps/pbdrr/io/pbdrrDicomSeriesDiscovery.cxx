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
#include "pbdrrDicomSeriesDiscovery.h"
#include "pbdrrDicomContent.h"
#include "pbdrrDicomFileCheck.h"
#include "pbdrrLoaderText.h"

#include "itkGDCMSeriesFileNames.h"

#include <algorithm>
#include <filesystem>
#include <set>

namespace pbdrr
{
namespace
{
/** The regular files of a directory, sorted by name (so that messages name them in a stable order). */
std::vector<std::string>
SortedRegularFiles(const std::string & directory)
{
  std::vector<std::string> files;
  for (const auto & entry : std::filesystem::directory_iterator(directory))
  {
    if (entry.is_regular_file())
    {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/** Refuses a directory that holds a DICOM file cut short, before GDCM reads it (GDCM may abort on such a file). */
void
RefuseTruncatedFiles(const std::vector<std::string> & files, const std::string & directory)
{
  std::vector<std::string> truncated;
  std::string              first;
  for (const auto & file : files)
  {
    const std::string problem = FindDicomTruncation(file);
    if (!problem.empty())
    {
      truncated.push_back(file);
      first = first.empty() ? problem : first;
    }
  }
  if (!truncated.empty())
  {
    Fail(std::to_string(truncated.size()) + " DICOM file(s) in " + directory +
         " are truncated or damaged: " + JoinNames(truncated) + " (" + first +
         "); pbdrr does not render a series with a slice cut short or left out: repair or remove them");
  }
}

/** The files no series took: says what they are, and refuses a directory holding damaged DICOM files (the slice it
 * held would be silently missing from a volume). */
void
SortOutOtherFiles(const std::vector<std::string> & directoryFiles,
                  const std::string &              directory,
                  DicomSeriesList &                list)
{
  std::set<std::string> taken;
  for (const auto & s : list.Series)
  {
    taken.insert(s.Files.begin(), s.Files.end());
  }
  std::vector<std::string> damaged, withoutImage, otherImages, directories;
  for (const auto & file : directoryFiles)
  {
    if (taken.count(file))
    {
      continue;
    }
    switch (ClassifyDicomFile(file))
    {
      case DicomContent::Damaged:
        damaged.push_back(file);
        break;
      case DicomContent::NoImage:
        withoutImage.push_back(file);
        break;
      case DicomContent::Directory:
        directories.push_back(file);
        break;
      case DicomContent::Image:
        otherImages.push_back(file);
        break;
      case DicomContent::NotDicom:
        list.NotDicom.push_back(file);
        break;
    }
  }
  if (!damaged.empty())
  {
    Fail(std::to_string(damaged.size()) + " DICOM file(s) in " + directory +
         " cannot be read (truncated or damaged): " + JoinNames(damaged) +
         "; pbdrr does not render a series with a slice left out: repair or remove them");
  }
  if (list.Series.empty())
  {
    Fail("no DICOM series found in directory " + directory);
  }
  if (!directories.empty())
  {
    list.Notes.push_back("ignored " + std::to_string(directories.size()) + " DICOM directory file(s) in " + directory +
                         " (a DICOMDIR: an index of the export, not an image): " + JoinNames(directories));
  }
  if (!withoutImage.empty())
  {
    list.Notes.push_back("ignored " + std::to_string(withoutImage.size()) + " DICOM object(s) without an image in " +
                         directory + " (reports, structure sets, ...): " + JoinNames(withoutImage));
  }
  if (!otherImages.empty())
  {
    list.Notes.push_back("ignored " + std::to_string(otherImages.size()) + " DICOM image(s) in " + directory +
                         " that belong to no series: " + JoinNames(otherImages));
  }
}
} // namespace

DicomSeriesList
FindDicomSeries(const std::string & directory)
{
  const std::vector<std::string> directoryFiles = SortedRegularFiles(directory);
  RefuseTruncatedFiles(directoryFiles, directory);
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(false);
  names->SetDirectory(directory);
  DicomSeriesList list;
  for (const auto & uid : names->GetSeriesUIDs())
  {
    list.Series.push_back({ uid, names->GetFileNames(uid) });
  }
  SortOutOtherFiles(directoryFiles, directory, list);
  return list;
}

const DicomSeries &
SelectDicomSeries(const DicomSeriesList &    list,
                  const std::string &        seriesUID,
                  const std::string &        directory,
                  std::vector<std::string> & notes)
{
  const auto & series = list.Series;
  if (!seriesUID.empty())
  {
    const auto found =
      std::find_if(series.begin(), series.end(), [&](const DicomSeries & s) { return s.UID == seriesUID; });
    if (found == series.end())
    {
      std::string available;
      for (const auto & s : series)
      {
        available += "\n  " + s.UID + " (" + std::to_string(s.Files.size()) + " files)";
      }
      Fail("series " + seriesUID + " is not in " + directory + "; available:" + available);
    }
    return *found;
  }
  const DicomSeries * chosen = &series.front(); // FindDicomSeries finds a series of at least one file, or fails
  size_t              largest = 0;
  for (const auto & s : series)
  {
    if (s.Files.size() > largest)
    {
      largest = s.Files.size();
      chosen = &s;
    }
  }
  if (series.size() > 1)
  {
    notes.push_back(directory + " holds " + std::to_string(series.size()) + " DICOM series; using the largest, " +
                    chosen->UID + " (" + std::to_string(largest) + " files); choose another with --series UID");
  }
  return *chosen;
}
} // namespace pbdrr
