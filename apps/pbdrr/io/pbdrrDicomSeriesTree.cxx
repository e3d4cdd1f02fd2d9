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
#include "pbdrrDicomSeriesTree.h"
#include "pbdrrDicomValues.h"
#include "pbdrrGdcmWarningCapture.h"
#include "pbdrrLoaderText.h"

#include "gdcmAttribute.h"
#include "gdcmReader.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace pbdrr
{
namespace
{
/** A DICOM string value without its padding (trailing spaces and NULs). */
std::string
Trimmed(const gdcm::DataSet & dataSet, const gdcm::Tag & tag)
{
  std::string value;
  if (!StringValue(dataSet, tag, value))
  {
    return "";
  }
  const size_t end = value.find_last_not_of(std::string(" \0", 2));
  return end == std::string::npos ? "" : value.substr(0, end + 1);
}

/** The summary of one series, from the header of its first file (without its pixel data). */
DicomSeriesSummary
Summarize(const DicomSeries & series, const std::string & directory)
{
  DicomSeriesSummary summary;
  size_t             slices = series.Files.size(); // files, or the frames of a multi-frame file
  bool               ctImage = false;
  summary.Series = series;
  summary.Directory = directory;
  gdcm::Reader reader;
  reader.SetFileName(series.Files.front().c_str());
  if (reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010)))
  {
    const gdcm::DataSet & dataSet = reader.GetFile().GetDataSet();
    summary.Description = Trimmed(dataSet, gdcm::Tag(0x0008, 0x103e));
    summary.Modality = Trimmed(dataSet, gdcm::Tag(0x0008, 0x0060));
    summary.ImageType = Trimmed(dataSet, gdcm::Tag(0x0008, 0x0008));
    summary.Tilt = Trimmed(dataSet, gdcm::Tag(0x0018, 0x1120));
    const std::string frames = Trimmed(dataSet, gdcm::Tag(0x0028, 0x0008));
    if (series.Files.size() == 1 && !frames.empty())
    {
      slices = static_cast<size_t>(std::max(1L, std::atol(frames.c_str())));
    }
    gdcm::Attribute<0x0028, 0x0010> rows{};
    gdcm::Attribute<0x0028, 0x0011> columns{};
    if (dataSet.FindDataElement(rows.GetTag()) && dataSet.FindDataElement(columns.GetTag()))
    {
      rows.SetFromDataSet(dataSet);
      columns.SetFromDataSet(dataSet);
      summary.Size =
        std::to_string(rows.GetValue()) + " x " + std::to_string(columns.GetValue()) + " x " + std::to_string(slices);
    }
    // CT Image Storage, Enhanced and Legacy Converted Enhanced CT: 1.2.840.10008.5.1.4.1.1.2[.x]. A secondary
    // capture labelled CT (an exam summary, a dose report) is not a volume.
    ctImage = Trimmed(dataSet, gdcm::Tag(0x0008, 0x0016)).rfind("1.2.840.10008.5.1.4.1.1.2", 0) == 0;
  }
  std::string imageType = summary.ImageType;
  std::transform(
    imageType.begin(), imageType.end(), imageType.begin(), [](unsigned char c) { return std::toupper(c); });
  summary.Localizer = imageType.find("LOCALIZER") != std::string::npos;
  summary.Volume = !summary.Localizer && ctImage && slices > 1;
  return summary;
}

/** The folders of a tree, the root first, then the others in name order. */
std::vector<std::string>
Folders(const std::string & root)
{
  std::vector<std::string> folders{ root };
  for (const auto & entry :
       std::filesystem::recursive_directory_iterator(root, std::filesystem::directory_options::skip_permission_denied))
  {
    if (entry.is_directory())
    {
      folders.push_back(entry.path().string());
    }
  }
  std::sort(folders.begin() + 1, folders.end());
  return folders;
}
} // namespace

std::vector<DicomSeriesSummary>
FindDicomSeriesTree(const std::string & root, std::vector<std::string> & notes)
{
  std::vector<DicomSeriesSummary> found;
  for (const std::string & folder : Folders(root))
  {
    const bool hasFiles = std::any_of(std::filesystem::directory_iterator(folder),
                                      std::filesystem::directory_iterator(),
                                      [](const auto & entry) { return entry.is_regular_file(); });
    if (!hasFiles)
    {
      continue;
    }
    try
    {
      GdcmWarningCapture    quiet;
      const DicomSeriesList list = FindDicomSeries(folder);
      for (const auto & series : list.Series)
      {
        found.push_back(Summarize(series, folder));
      }
    }
    catch (const std::runtime_error & e)
    {
      // A folder of the export without a series (only its DICOMDIR, say), or with damaged files: named, not fatal.
      const std::string reason = e.what();
      if (reason.rfind("no DICOM series found", 0) != 0)
      {
        notes.push_back("skipped " + folder + ": " + reason);
      }
    }
  }
  return found;
}

const DicomSeriesSummary &
SelectDicomVolume(const std::vector<DicomSeriesSummary> & series,
                  const std::string &                     seriesUID,
                  const std::string &                     root,
                  std::vector<std::string> &              notes)
{
  if (!seriesUID.empty())
  {
    const auto found = std::find_if(
      series.begin(), series.end(), [&](const DicomSeriesSummary & s) { return s.Series.UID == seriesUID; });
    if (found == series.end())
    {
      Fail("series " + seriesUID + " is not in " + root + "; pbdrr --list-series " + root + " lists those there");
    }
    if (found->Localizer)
    {
      Fail("series " + seriesUID + " is a localizer (" + found->ImageType + "): a projection, not a volume");
    }
    return *found;
  }
  const DicomSeriesSummary * chosen = nullptr;
  for (const auto & s : series)
  {
    if (s.Volume && (!chosen || s.Series.Files.size() > chosen->Series.Files.size()))
    {
      chosen = &s;
    }
  }
  if (!chosen)
  {
    Fail("no CT volume series in " + root + " (localizers and other objects are not volumes); pbdrr --list-series " +
         root + " lists what is there");
  }
  if (series.size() > 1)
  {
    notes.push_back(root + " holds " + std::to_string(series.size()) + " DICOM series; using the largest CT volume, " +
                    chosen->Series.UID + " (" + chosen->Description + ", " + chosen->Size + ", in " +
                    chosen->Directory + "); choose another with --series UID (pbdrr --list-series " + root + ")");
  }
  return *chosen;
}

std::string
FormatDicomSeriesTable(const std::vector<DicomSeriesSummary> & series)
{
  std::ostringstream table;
  table << "kind       modality  size (rows x cols x slices)  tilt (deg)  description  |  series UID  |  folder\n";
  for (const auto & s : series)
  {
    table << std::left << std::setw(11)
          << (s.Localizer ? "localizer"
              : s.Volume  ? "volume"
                          : "other")
          << std::setw(10) << (s.Modality.empty() ? "-" : s.Modality) << std::setw(29) << s.Size << std::setw(12)
          << (s.Tilt.empty() ? "-" : s.Tilt) << (s.Description.empty() ? "-" : s.Description) << "  |  "
          << (s.Series.UID.empty() ? "(no UID)" : s.Series.UID) << "  |  " << s.Directory << "\n";
  }
  return table.str();
}
} // namespace pbdrr
