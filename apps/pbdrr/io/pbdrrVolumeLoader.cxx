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
#include "pbdrrVolumeLoader.h"
#include "pbdrrDicomFileCheck.h"
#include "pbdrrDicomContent.h"
#include "pbdrrDicomMultiFrame.h"
#include "pbdrrDicomSeriesDiscovery.h"
#include "pbdrrDicomSeriesReader.h"
#include "pbdrrDicomSeriesTree.h"
#include "pbdrrGdcmWarningCapture.h"
#include "pbdrrLoaderText.h"
#include "pbdrrVolumeFileReader.h"

#include "itkDRRImageFileIntegrity.h"
#include "itkGDCMImageIO.h"
#include "itkImageIOFactory.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <sys/stat.h>

namespace pbdrr
{
namespace
{
/** Whether a directory holds no file but a DICOMDIR-like index and has folders below it: an export's root. */
bool
IsExportRoot(const std::string & directory)
{
  bool folders = false;
  for (const auto & entry : std::filesystem::directory_iterator(directory))
  {
    if (entry.is_directory())
    {
      folders = true;
    }
    else if (entry.is_regular_file())
    {
      const DicomContent content = ClassifyDicomFile(entry.path().string());
      if (content != DicomContent::Directory && content != DicomContent::NotDicom)
      {
        return false; // DICOM objects of its own: a series directory
      }
    }
  }
  return folders;
}

/** The series to read from a directory: its own (FindDicomSeries), or for an export's root the largest CT volume in
 * the folders below it (never a localizer). notDicom: the directory's files that are not DICOM. */
DicomSeries
ChooseDicomSeries(const std::string &        directory,
                  const std::string &        seriesUID,
                  LoadedVolume &             loaded,
                  std::vector<std::string> & notDicom)
{
  if (IsExportRoot(directory))
  {
    const auto tree = FindDicomSeriesTree(directory, loaded.Notes);
    return SelectDicomVolume(tree, seriesUID, directory, loaded.Notes).Series;
  }
  const DicomSeriesList list = FindDicomSeries(directory);
  loaded.Notes = list.Notes;
  notDicom = list.NotDicom;
  return SelectDicomSeries(list, seriesUID, directory, loaded.Notes);
}

/** A directory: its DICOM series (found, then one selected), read as a volume. */
LoadedVolume
LoadDicomDirectory(const std::string & directory, const std::string & seriesUID, const LoadProgress & progress)
{
  GdcmWarningCapture       quiet; // GDCM's own errors while scanning: pbdrr words the problems itself
  LoadedVolume             loaded;
  std::vector<std::string> notDicom;
  const DicomSeries        chosen = ChooseDicomSeries(directory, seriesUID, loaded, notDicom);
  if (chosen.Files.size() == 1)
  {
    // One file: a multi-frame volume, or a single slice (refused as 2D).
    loaded.Set(ReadDicomFile(chosen.Files[0], loaded.Notes));
  }
  else
  {
    ReadDicomSeries(chosen.Files, notDicom, directory, loaded, progress);
  }
  const std::string name = chosen.UID.empty() ? std::string("without a Series Instance UID") : chosen.UID;
  loaded.Description = "DICOM series " + name + " (" + std::to_string(chosen.Files.size()) + " files) in " + directory;
  return loaded;
}

/** A file: a DICOM file (refused if cut short, before GDCM reads it), or any image file ITK reads. */
LoadedVolume
LoadVolumeFile(const std::string & input)
{
  LoadedVolume      loaded;
  const std::string truncation = FindDicomTruncation(input);
  if (!truncation.empty())
  {
    Fail("cannot read " + input + ": the DICOM file is truncated or damaged (" + truncation + ")");
  }
  // The integrity check (DRRImageFileIntegrity). Of an uncompressed file it is a stat, done before the read; of a
  // compressed one it inflates the file to its end, as the read does, so it runs beside the read on another core, and
  // its verdict, taken after the read or its failure, refuses a volume the reader filled in silently.
  std::future<std::string> damage =
    std::async(std::launch::async, [input] { return itk::DRRImageFileIntegrity::FindDamage(input); });
  // Its verdict is taken once: the future is no longer valid() after get().
  const auto refuseDamaged = [&damage, &input] {
    if (!damage.valid())
    {
      return;
    }
    const std::string found = damage.get();
    if (!found.empty())
    {
      Fail("cannot read " + input + ": " + found);
    }
  };
  if (damage.wait_for(std::chrono::milliseconds(50)) == std::future_status::ready)
  {
    refuseDamaged();
  }
  try
  {
    auto io = itk::ImageIOFactory::CreateImageIO(input.c_str(), itk::IOFileModeEnum::ReadMode);
    if (!io)
    {
      Fail("cannot read " + input + ": not an image format ITK knows (DICOM directory, .mha, .nrrd, .nii, ...)");
    }
    if (dynamic_cast<itk::GDCMImageIO *>(io.GetPointer()))
    {
      // A DICOM file alone: a multi-frame volume, placed by its frame positions, or a 2D slice (refused).
      loaded.Set(ReadDicomFile(input, loaded.Notes));
    }
    else
    {
      io->SetFileName(input);
      io->ReadImageInformation();
      ReadVolumeFileInto(input, io, loaded);
    }
  }
  catch (...)
  {
    refuseDamaged();
    throw;
  }
  refuseDamaged();
  loaded.Description = "file " + input;
  return loaded;
}
} // namespace

void
LoadedVolume::Set(HUVolumeType::Pointer volume)
{
  if (!volume)
  {
    ThrowNotSet();
  }
  m_HU = volume;
  m_Image = nullptr;
}

void
LoadedVolume::Set(VolumeType::Pointer volume)
{
  if (!volume)
  {
    ThrowNotSet();
  }
  m_Image = volume;
  m_HU = nullptr;
}

VolumeType::Pointer
LoadedVolume::AsFloat() const
{
  if (m_Image)
  {
    return m_Image;
  }
  if (!m_HU)
  {
    ThrowNotSet();
  }
  auto volume = VolumeType::New();
  volume->CopyInformation(m_HU);
  volume->SetRegions(m_HU->GetBufferedRegion());
  volume->Allocate();
  std::copy(m_HU->GetBufferPointer(),
            m_HU->GetBufferPointer() + m_HU->GetBufferedRegion().GetNumberOfPixels(),
            volume->GetBufferPointer());
  return volume;
}

const itk::ImageBase<3> *
LoadedVolume::Grid() const
{
  return Visit([](const itk::ImageBase<3> * volume) { return volume; });
}

void
LoadedVolume::ThrowNotSet()
{
  throw std::logic_error("pbdrr: a LoadedVolume used before a volume was set in it");
}

LoadedVolume
LoadVolume(const std::string & input, const std::string & seriesUID, const LoadProgress & progress)
{
  struct stat status;
  if (stat(input.c_str(), &status) != 0)
  {
    Fail("input " + input + " does not exist");
  }
  try
  {
    return S_ISDIR(status.st_mode) ? LoadDicomDirectory(input, seriesUID, progress) : LoadVolumeFile(input);
  }
  catch (const itk::ExceptionObject & e)
  {
    Fail("cannot read " + input + ": " + e.GetDescription());
  }
}

std::string
ListDicomSeries(const std::string & root)
{
  struct stat status;
  if (stat(root.c_str(), &status) != 0 || !S_ISDIR(status.st_mode))
  {
    Fail("--list-series: " + root + " is not a directory");
  }
  GdcmWarningCapture       quiet;
  std::vector<std::string> notes;
  const auto               series = FindDicomSeriesTree(root, notes);
  if (series.empty())
  {
    Fail("no DICOM series in " + root + " or the folders below it" + (notes.empty() ? "" : ": " + notes.front()));
  }
  std::string text = FormatDicomSeriesTable(series);
  for (const auto & note : notes)
  {
    text += "note: " + note + "\n";
  }
  return text;
}
} // namespace pbdrr
