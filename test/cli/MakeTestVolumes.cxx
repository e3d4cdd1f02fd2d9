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
// MakeTestVolumes DIR: writes the tiny inputs of the pbdrr command-line tests into DIR (see test/cli/CMakeLists.txt):
//   phantom.mha (16 x 16 x 12 short HU), image2d.mha, image4d.mha, vector.mha (3 components), garbage.mha (text),
//   truncated.mha (a header whose pixel data is cut short), isdir.mha/ (a directory), geometry files, and DICOM
//   series directories: dicom_good, dicom_missing, dicom_uneven, dicom_tilt, dicom_duplicate, dicom_orientation,
//   dicom_single, dicom_two_series, dicom_empty, dicom_text_only.
// The slice positions written into the DICOM files are read back with GDCM and checked, so a test that expects
// "missing slice" really gets a series with a missing slice.
#include "itkGDCMImageIO.h"
#include "itkImage.h"
#include "itkImageFileWriter.h"
#include "itkMetaDataObject.h"
#include "itkVector.h"
#include "gdcmScanner.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef LARGE_SERIES_UID
#define LARGE_SERIES_UID "2.25.7147300001"
#endif
#ifndef SMALL_SERIES_UID
#define SMALL_SERIES_UID "2.25.7147300002"
#endif

namespace fs = std::filesystem;

namespace
{
using Vector3 = std::array<double, 3>;
using Orientation = std::array<double, 6>;
constexpr Orientation axial{ { 1, 0, 0, 0, 1, 0 } };
const std::string     studyUID = "2.25.7147100001";

/** A value that looks like a head: air, a water cylinder, a bone core. */
short
PhantomValue(double x, double y)
{
  const double r = std::sqrt(x * x + y * y);
  return r < 2.5 ? 1000 : (r < 6.5 ? 0 : -1000);
}

std::string
Join(const double * values, size_t count)
{
  std::ostringstream s;
  s.precision(10);
  for (size_t i = 0; i < count; ++i)
  {
    s << (i ? "\\" : "") << values[i];
  }
  return s.str();
}

fs::path
FreshDirectory(const fs::path & path)
{
  fs::remove_all(path);
  fs::create_directories(path);
  return path;
}

void
WritePhantom(const fs::path & file)
{
  using ImageType = itk::Image<short, 3>;
  auto                   image = ImageType::New();
  ImageType::SizeType    size{ { 16, 16, 12 } };
  ImageType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 1.0;
  spacing[2] = 1.5;
  image->SetRegions(size);
  image->SetSpacing(spacing);
  ImageType::PointType origin;
  origin[0] = -7.5;
  origin[1] = -7.5;
  origin[2] = -8.25;
  image->SetOrigin(origin);
  image->Allocate();
  for (unsigned z = 0; z < size[2]; ++z)
  {
    for (unsigned y = 0; y < size[1]; ++y)
    {
      for (unsigned x = 0; x < size[0]; ++x)
      {
        image->SetPixel({ { x, y, z } }, PhantomValue(x - 7.5, y - 7.5));
      }
    }
  }
  itk::WriteImage(image, file.string());
}

template <typename TImage>
void
WriteConstant(const fs::path & file, const typename TImage::SizeType & size, const typename TImage::PixelType & value)
{
  auto image = TImage::New();
  image->SetRegions(size);
  image->Allocate();
  image->FillBuffer(value);
  itk::WriteImage(image, file.string());
}

void
WriteText(const fs::path & file, const std::string & text)
{
  std::ofstream out(file);
  out << text;
  if (!out)
  {
    throw std::runtime_error("cannot write " + file.string());
  }
}

/** One axial-looking CT slice, 16 x 16 at 0.9 mm, with the given patient position, orientation and UIDs. */
void
WriteSlice(const fs::path &    file,
           const std::string & seriesUID,
           unsigned            instance,
           const Vector3 &     position,
           const Orientation & orientation)
{
  using SliceType = itk::Image<short, 2>;
  auto                   slice = SliceType::New();
  SliceType::SizeType    size{ { 16, 16 } };
  SliceType::SpacingType spacing(0.9);
  SliceType::PointType   origin;
  origin[0] = position[0];
  origin[1] = position[1];
  slice->SetRegions(size);
  slice->SetSpacing(spacing);
  slice->SetOrigin(origin);
  slice->Allocate();
  for (unsigned y = 0; y < size[1]; ++y)
  {
    for (unsigned x = 0; x < size[0]; ++x)
    {
      slice->SetPixel({ { x, y } }, PhantomValue(0.9 * (x - 7.5), 0.9 * (y - 7.5)));
    }
  }

  auto io = itk::GDCMImageIO::New();
  io->KeepOriginalUIDOn(); // write our UIDs, not fresh ones: the tests select series by UID
  itk::MetaDataDictionary dictionary;
  auto                    set = [&](const std::string & tag, const std::string & value) {
    itk::EncapsulateMetaData<std::string>(dictionary, tag, value);
  };
  set("0008|0016", "1.2.840.10008.5.1.4.1.1.2"); // CT Image Storage
  set("0008|0018", seriesUID + "." + std::to_string(instance));
  set("0008|0060", "CT");
  set("0010|0010", "PBDRR^TEST");
  set("0010|0020", "PBDRR-CLI");
  set("0020|000d", studyUID);
  set("0020|000e", seriesUID);
  set("0020|0052", studyUID + ".1");
  set("0020|0013", std::to_string(instance));
  set("0020|0032", Join(position.data(), 3));
  set("0020|0037", Join(orientation.data(), 6));
  set("0018|0050", "2.5");
  set("0028|1052", "0");
  set("0028|1053", "1");
  io->SetMetaDataDictionary(dictionary);
  slice->SetMetaDataDictionary(dictionary);

  auto writer = itk::ImageFileWriter<SliceType>::New();
  writer->SetInput(slice);
  writer->SetImageIO(io);
  writer->SetFileName(file.string());
  writer->Update();
}

struct SliceSpec
{
  Vector3     position;
  Orientation orientation{ axial };
};

/** Writes a series (files IM0001.dcm, ...) and reads the positions and orientations back through GDCM. */
void
WriteSeries(const fs::path &               directory,
            const std::string &            seriesUID,
            const std::vector<SliceSpec> & slices,
            const std::string &            prefix = "IM")
{
  std::vector<std::string> files;
  for (size_t i = 0; i < slices.size(); ++i)
  {
    char name[64];
    std::snprintf(name, sizeof(name), "%s%04zu.dcm", prefix.c_str(), i + 1);
    const fs::path file = directory / name;
    WriteSlice(file, seriesUID, static_cast<unsigned>(i + 1), slices[i].position, slices[i].orientation);
    files.push_back(file.string());
  }

  const gdcm::Tag positionTag(0x0020, 0x0032), orientationTag(0x0020, 0x0037), seriesTag(0x0020, 0x000e);
  gdcm::Scanner   scanner;
  scanner.AddTag(positionTag);
  scanner.AddTag(orientationTag);
  scanner.AddTag(seriesTag);
  if (!scanner.Scan(files))
  {
    throw std::runtime_error("cannot scan the DICOM files written in " + directory.string());
  }
  auto numbers = [](const char * text) {
    std::vector<double> values;
    std::string         s = text ? text : "";
    for (char & c : s)
    {
      c = c == '\\' ? ' ' : c;
    }
    std::istringstream stream(s);
    for (double v; stream >> v;)
    {
      values.push_back(v);
    }
    return values;
  };
  for (size_t i = 0; i < files.size(); ++i)
  {
    const std::vector<double> position = numbers(scanner.GetValue(files[i].c_str(), positionTag));
    const std::vector<double> orientation = numbers(scanner.GetValue(files[i].c_str(), orientationTag));
    const char *              series = scanner.GetValue(files[i].c_str(), seriesTag);
    bool                      ok = position.size() == 3 && orientation.size() == 6 && series != nullptr;
    for (size_t k = 0; ok && k < 3; ++k)
    {
      ok = std::abs(position[k] - slices[i].position[k]) < 1e-4;
    }
    for (size_t k = 0; ok && k < 6; ++k)
    {
      ok = std::abs(orientation[k] - slices[i].orientation[k]) < 1e-4;
    }
    // DICOM pads odd-length UIDs with a NUL.
    ok = ok && std::string(series).substr(0, seriesUID.size()) == seriesUID;
    if (!ok)
    {
      throw std::runtime_error(files[i] + ": the image position/orientation/series UID read back differ from those " +
                               "written (position " + Join(slices[i].position.data(), 3) + ")");
    }
  }
}

std::vector<SliceSpec>
AxialStack(size_t count, double step, double firstZ = -10.0)
{
  std::vector<SliceSpec> slices;
  for (size_t i = 0; i < count; ++i)
  {
    slices.push_back({ { { -6.75, -6.75, firstZ + step * i } } });
  }
  return slices;
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIRECTORY" << std::endl;
    return 2;
  }
  try
  {
    const fs::path root = argv[1];
    fs::create_directories(root);

    // Volume files.
    WritePhantom(root / "phantom.mha");
    WriteConstant<itk::Image<short, 2>>(root / "image2d.mha", { { 16, 16 } }, 0);
    WriteConstant<itk::Image<short, 4>>(root / "image4d.mha", { { 4, 4, 4, 2 } }, 0);
    WriteConstant<itk::Image<itk::Vector<float, 3>, 3>>(
      root / "vector.mha", { { 8, 8, 8 } }, itk::Vector<float, 3>(0.0f));
    WriteText(root / "garbage.mha", "this is not an image\nNDims = banana\n");
    WritePhantom(root / "truncated.mha");
    fs::resize_file(root / "truncated.mha", fs::file_size(root / "truncated.mha") - 1000);
    FreshDirectory(root / "isdir.mha");

    // Geometry files.
    WriteText(root / "geometry_32.txt",
              "# a 32 x 32 detector\nprojection perspective\nsad 1000\nsid 1500\ngantry 90\ncols 32\nrows 32\n"
              "spacing 1.2 1.2\n");
    WriteText(root / "geometry_badkey.txt", "sad 1000\nfrobnicate 3\n");
    WriteText(root / "geometry_badvalue.txt", "sad 1000\nsid 1500\ncols many\n");

    // DICOM series: 8 axial slices 2.5 mm apart, and broken variants.
    const std::string uid = "2.25.7147200";
    WriteSeries(FreshDirectory(root / "dicom_good"), uid + "1", AxialStack(8, 2.5));

    std::vector<SliceSpec> missing = AxialStack(8, 2.5);
    missing.erase(missing.begin() + 4);
    WriteSeries(FreshDirectory(root / "dicom_missing"), uid + "2", missing);

    std::vector<SliceSpec> uneven = AxialStack(8, 2.5);
    for (size_t i = 5; i < uneven.size(); ++i)
    {
      uneven[i].position[2] += 0.6; // one gap of 3.1 mm among 2.5 mm gaps
    }
    WriteSeries(FreshDirectory(root / "dicom_uneven"), uid + "3", uneven);

    std::vector<SliceSpec> tilt = AxialStack(8, 2.5);
    for (size_t i = 0; i < tilt.size(); ++i)
    {
      tilt[i].position[1] += 0.5 * i; // orientation stays axial, the positions drift in y: a tilted gantry
    }
    WriteSeries(FreshDirectory(root / "dicom_tilt"), uid + "4", tilt);

    std::vector<SliceSpec> duplicate = AxialStack(8, 2.5);
    duplicate[5].position = duplicate[4].position;
    WriteSeries(FreshDirectory(root / "dicom_duplicate"), uid + "5", duplicate);

    std::vector<SliceSpec> orientation = AxialStack(8, 2.5);
    orientation[3].orientation = { { 1, 0, 0, 0, 0.8, -0.6 } };
    WriteSeries(FreshDirectory(root / "dicom_orientation"), uid + "6", orientation);

    WriteSeries(FreshDirectory(root / "dicom_single"), uid + "7", AxialStack(1, 2.5));

    const fs::path two = FreshDirectory(root / "dicom_two_series");
    WriteSeries(two, LARGE_SERIES_UID, AxialStack(8, 2.5), "A");
    WriteSeries(two, SMALL_SERIES_UID, AxialStack(5, 3.0, 20.0), "B");

    FreshDirectory(root / "dicom_empty");
    WriteText(FreshDirectory(root / "dicom_text_only") / "README.txt", "no DICOM here\n");
  }
  catch (const itk::ExceptionObject & e)
  {
    std::cerr << "MakeTestVolumes: " << e.GetDescription() << std::endl;
    return 1;
  }
  catch (const std::exception & e)
  {
    std::cerr << "MakeTestVolumes: " << e.what() << std::endl;
    return 1;
  }
  std::cout << "MakeTestVolumes: wrote the test inputs into " << argv[1] << std::endl;
  return 0;
}
