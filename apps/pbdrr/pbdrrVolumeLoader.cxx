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

#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImageFileReader.h"
#include "itkImageIOFactory.h"
#include "itkImageSeriesReader.h"
#include "gdcmScanner.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

namespace pbdrr
{
namespace
{
using Vector3 = std::array<double, 3>;

[[noreturn]] void
Fail(const std::string & message)
{
  throw std::runtime_error(message);
}

bool
ParseNumbers(const char * text, size_t count, std::vector<double> & numbers)
{
  numbers.clear();
  if (text == nullptr)
  {
    return false;
  }
  std::string s(text);
  std::replace(s.begin(), s.end(), '\\', ' ');
  std::istringstream stream(s);
  for (double v; stream >> v;)
  {
    numbers.push_back(v);
  }
  return numbers.size() == count;
}

Vector3
Cross(const Vector3 & a, const Vector3 & b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

double
Dot(const Vector3 & a, const Vector3 & b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

std::string
Millimetres(double value)
{
  std::ostringstream s;
  s.precision(4);
  s << value << " mm";
  return s.str();
}

/** Checks that the files form one regular 3D grid; returns the slice spacing (mm). */
double
CheckSeriesGeometry(const std::vector<std::string> & files)
{
  const gdcm::Tag positionTag(0x0020, 0x0032);
  const gdcm::Tag orientationTag(0x0020, 0x0037);
  const gdcm::Tag rowsTag(0x0028, 0x0010);
  const gdcm::Tag columnsTag(0x0028, 0x0011);
  gdcm::Scanner   scanner;
  scanner.AddTag(positionTag);
  scanner.AddTag(orientationTag);
  scanner.AddTag(rowsTag);
  scanner.AddTag(columnsTag);
  if (!scanner.Scan(files))
  {
    Fail("cannot scan the DICOM files of the series");
  }
  std::vector<double>  orientation0;
  std::vector<Vector3> positions;
  std::string          rows0, columns0;
  for (const std::string & file : files)
  {
    std::vector<double> orientation, position;
    if (!ParseNumbers(scanner.GetValue(file.c_str(), orientationTag), 6, orientation) ||
        !ParseNumbers(scanner.GetValue(file.c_str(), positionTag), 3, position))
    {
      Fail("DICOM file " + file + " has no image position/orientation (not a CT slice?)");
    }
    const char * rows = scanner.GetValue(file.c_str(), rowsTag);
    const char * columns = scanner.GetValue(file.c_str(), columnsTag);
    if (positions.empty())
    {
      orientation0 = orientation;
      rows0 = rows ? rows : "";
      columns0 = columns ? columns : "";
    }
    else
    {
      for (size_t i = 0; i < 6; ++i)
      {
        if (std::abs(orientation[i] - orientation0[i]) > 1e-4)
        {
          Fail("the slices of the series have different orientations (" + file + "): not one volume");
        }
      }
      if ((rows ? rows : "") != rows0 || (columns ? columns : "") != columns0)
      {
        Fail("the slices of the series have different sizes (" + file + "): not one volume");
      }
    }
    positions.push_back({ position[0], position[1], position[2] });
  }
  if (positions.size() < 2)
  {
    return 1.0;
  }
  const Vector3       rowDirection{ orientation0[0], orientation0[1], orientation0[2] };
  const Vector3       columnDirection{ orientation0[3], orientation0[4], orientation0[5] };
  const Vector3       normal = Cross(rowDirection, columnDirection);
  std::vector<double> depth(positions.size());
  for (size_t i = 0; i < positions.size(); ++i)
  {
    depth[i] = Dot(positions[i], normal);
  }
  std::vector<size_t> order(positions.size());
  for (size_t i = 0; i < order.size(); ++i)
  {
    order[i] = i;
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return depth[a] < depth[b]; });
  std::vector<double> gaps;
  for (size_t i = 1; i < order.size(); ++i)
  {
    const Vector3 & a = positions[order[i - 1]];
    const Vector3 & b = positions[order[i]];
    const Vector3   step{ b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double    along = Dot(step, normal);
    const double    across = std::sqrt(std::max(0.0, Dot(step, step) - along * along));
    if (along < 1e-3)
    {
      Fail("two slices of the series lie at the same position (" + Millimetres(depth[order[i]]) +
           " along the slice normal): duplicated or mixed series");
    }
    if (across > 1e-3 * along + 0.01)
    {
      Fail("the slice positions are not along the slice normal (gantry tilt or sheared series: each slice is "
           "shifted " +
           Millimetres(across) + " sideways per " + Millimetres(along) +
           " step); pbdrr does not render tilted series: resample to an orthogonal grid first");
    }
    gaps.push_back(along);
  }
  std::vector<double> sorted = gaps;
  std::sort(sorted.begin(), sorted.end());
  const double spacing = sorted[sorted.size() / 2];
  for (size_t i = 0; i < gaps.size(); ++i)
  {
    if (std::abs(gaps[i] - spacing) > 0.01 * spacing + 1e-3)
    {
      const double       ratio = gaps[i] / spacing;
      const bool         missing = ratio > 1.5 && std::abs(ratio - std::round(ratio)) < 0.05;
      std::ostringstream message;
      message << (missing ? "missing slice(s)" : "uneven slice spacing") << ": slices " << i << " and " << i + 1
              << " (at " << Millimetres(depth[order[i]]) << " and " << Millimetres(depth[order[i + 1]])
              << " along the normal) are " << Millimetres(gaps[i]) << " apart, the series' spacing is "
              << Millimetres(spacing);
      if (missing)
      {
        message << " (" << std::lround(ratio) - 1 << " slice(s) missing)";
      }
      message << "; pbdrr does not render it rather than render it wrong";
      Fail(message.str());
    }
  }
  return spacing;
}

VolumeType::Pointer
ReadFile(const std::string & path, const itk::ImageIOBase::Pointer & io)
{
  if (io->GetNumberOfDimensions() != 3)
  {
    Fail(path + " is a " + std::to_string(io->GetNumberOfDimensions()) +
         "D image; pbdrr needs a 3D volume (a CT series or volume file)");
  }
  if (io->GetNumberOfComponents() != 1)
  {
    Fail(path + " has " + std::to_string(io->GetNumberOfComponents()) +
         " components per voxel; pbdrr needs scalar voxels (HU or mu)");
  }
  auto reader = itk::ImageFileReader<VolumeType>::New();
  reader->SetFileName(path);
  reader->SetImageIO(io);
  // Some readers (MetaImage) report a short read on std::cerr and carry on: listen, and refuse such a volume.
  std::ostringstream readerMessages;
  std::streambuf *   standardError = std::cerr.rdbuf(readerMessages.rdbuf());
  try
  {
    reader->Update();
  }
  catch (...)
  {
    std::cerr.rdbuf(standardError);
    throw;
  }
  std::cerr.rdbuf(standardError);
  const std::string messages = readerMessages.str();
  if (messages.find("not read completely") != std::string::npos || messages.find("rror") != std::string::npos)
  {
    Fail("cannot read " + path + ": the file is truncated or damaged (" + messages.substr(0, messages.find('\n')) +
         ")");
  }
  std::cerr << messages;
  VolumeType::Pointer image = reader->GetOutput();
  image->DisconnectPipeline(); // the volume is data from now on: no reader re-executes behind it
  return image;
}

LoadedVolume
LoadDicomDirectory(const std::string & directory, const std::string & seriesUID)
{
  LoadedVolume loaded;
  auto         names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(false);
  names->SetDirectory(directory);
  const std::vector<std::string> series = names->GetSeriesUIDs();
  if (series.empty())
  {
    Fail("no DICOM series found in directory " + directory);
  }
  std::string chosen;
  if (!seriesUID.empty())
  {
    if (std::find(series.begin(), series.end(), seriesUID) == series.end())
    {
      std::string available;
      for (const auto & s : series)
      {
        available += "\n  " + s + " (" + std::to_string(names->GetFileNames(s).size()) + " files)";
      }
      Fail("series " + seriesUID + " is not in " + directory + "; available:" + available);
    }
    chosen = seriesUID;
  }
  else
  {
    size_t largest = 0;
    for (const auto & s : series)
    {
      const size_t count = names->GetFileNames(s).size();
      if (count > largest)
      {
        largest = count;
        chosen = s;
      }
    }
    if (series.size() > 1)
    {
      loaded.Notes.push_back(directory + " holds " + std::to_string(series.size()) +
                             " DICOM series; using the largest, " + chosen + " (" + std::to_string(largest) +
                             " files); choose another with --series UID");
    }
  }
  const std::vector<std::string> files = names->GetFileNames(chosen);
  if (files.size() == 1)
  {
    // One file: a multi-frame volume, or a single slice (refused as 2D by ReadFile).
    auto io = itk::GDCMImageIO::New();
    io->SetFileName(files[0]);
    io->ReadImageInformation();
    loaded.Image = ReadFile(files[0], io.GetPointer());
    if (loaded.Image->GetLargestPossibleRegion().GetSize()[2] < 2)
    {
      Fail("the DICOM series in " + directory + " is a single 2D slice; pbdrr needs a volume");
    }
  }
  else
  {
    const double spacing = CheckSeriesGeometry(files);
    auto         reader = itk::ImageSeriesReader<VolumeType>::New();
    reader->SetImageIO(itk::GDCMImageIO::New());
    reader->SetFileNames(files);
    reader->Update();
    loaded.Image = reader->GetOutput();
    loaded.Image->DisconnectPipeline();
    auto imageSpacing = loaded.Image->GetSpacing();
    imageSpacing[2] = spacing;
    loaded.Image->SetSpacing(imageSpacing);
  }
  loaded.Description = "DICOM series " + chosen + " (" + std::to_string(files.size()) + " files) in " + directory;
  return loaded;
}
} // namespace

LoadedVolume
LoadVolume(const std::string & input, const std::string & seriesUID)
{
  struct stat status;
  if (stat(input.c_str(), &status) != 0)
  {
    Fail("input " + input + " does not exist");
  }
  LoadedVolume loaded;
  try
  {
    if (S_ISDIR(status.st_mode))
    {
      loaded = LoadDicomDirectory(input, seriesUID);
    }
    else
    {
      auto io = itk::ImageIOFactory::CreateImageIO(input.c_str(), itk::IOFileModeEnum::ReadMode);
      if (!io)
      {
        Fail("cannot read " + input + ": not an image format ITK knows (DICOM directory, .mha, .nrrd, .nii, ...)");
      }
      io->SetFileName(input);
      io->ReadImageInformation();
      loaded.Image = ReadFile(input, io);
      loaded.Description = "file " + input;
    }
  }
  catch (const itk::ExceptionObject & e)
  {
    Fail("cannot read " + input + ": " + e.GetDescription());
  }
  return loaded;
}
} // namespace pbdrr
