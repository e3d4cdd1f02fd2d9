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
// MakeTestVolumes DIR [J2K]: writes the tiny inputs of the pbdrr command-line tests into DIR (see
// test/cli/CMakeLists.txt):
//   phantom.mha (16 x 16 x 12 short HU), register_phantom.mha (asymmetric bone blocks), image2d.mha, image4d.mha,
//   vector.mha (3 components), garbage.mha (text), truncated.mha (a header whose pixel data is cut short), isdir.mha/
//   (a directory), nan.mha and inf.mha (a non-finite voxel), empty.mha (no voxels), float_extremes.mha (HU from -1e30
//   to 1e6), geometry files good and bad, dicom_jpeg2000_truncated (a copy of the JPEG 2000 series J2K with one slice
//   cut short, if J2K is given), and DICOM series directories: dicom_good, dicom_missing, dicom_uneven, dicom_tilt (a
//   gantry tilt: positions drift 0.5 mm in y per slice), dicom_tilt_uneven (the drift changes), dicom_duplicate,
//   dicom_orientation, dicom_single, dicom_two_series, dicom_empty, dicom_text_only, dicom_truncated (a slice cut
//   short), dicom_with_report (non-image objects beside the slices), dicom_with_dirfile (a DICOMDIR named DIRFILE
//   beside the slices, as a Philips export has it), dicom_export (an export tree: DIRFILE, a localizer series, a volume
//   and a smaller series in folders), CT localizers (localizer_lateral.dcm, and _table_along_columns, _no_distances,
//   _detector_inside, _axial), projection matrices (matrix_view.P.txt, the view of matrix_view.txt; matrix_two_rows,
//   _row_of_3, _nan, _singular, _skewed) and multi-frame files: dicom_multiframe (and _descending,
//   _uneven, _shuffled, _legacy, _nogroups, _nowhere).
// The slice positions written into the DICOM files are read back with GDCM and checked, so a test that expects
// "missing slice" really gets a series with a missing slice.
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkGDCMImageIO.h"
#include "itkImage.h"
#include "itkImageFileWriter.h"
#include "itkMetaDataObject.h"
#include "itkVector.h"
#include "gdcmReader.h"
#include "gdcmScanner.h"
#include "gdcmSequenceOfItems.h"
#include "gdcmWriter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <iostream>
#include <limits>
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

/** A short volume of the given grid (mm), its voxel (x, y, z) set to value(x, y, z). */
itk::Image<short, 3>::Pointer
MakeShortVolume(const itk::Size<3> &                                       size,
                const std::array<double, 3> &                              spacing,
                const std::array<double, 3> &                              origin,
                const std::function<short(unsigned, unsigned, unsigned)> & value)
{
  using ImageType = itk::Image<short, 3>;
  auto image = ImageType::New();
  image->SetRegions(size);
  image->SetSpacing(spacing.data());
  image->SetOrigin(origin.data());
  image->Allocate();
  for (unsigned z = 0; z < size[2]; ++z)
  {
    for (unsigned y = 0; y < size[1]; ++y)
    {
      for (unsigned x = 0; x < size[0]; ++x)
      {
        image->SetPixel({ { x, y, z } }, value(x, y, z));
      }
    }
  }
  return image;
}

void
WritePhantom(const fs::path & file)
{
  const auto image = MakeShortVolume({ { 16, 16, 12 } },
                                     { { 1.0, 1.0, 1.5 } },
                                     { { -7.5, -7.5, -8.25 } },
                                     [](unsigned x, unsigned y, unsigned) { return PhantomValue(x - 7.5, y - 7.5); });
  itk::WriteImage(image, file.string());
}

/** A label image on the phantom's grid (moved along x by shiftInMillimetres), its voxel (x, y, z) set to label(x). */
template <typename TImage, typename TLabel>
void
WriteLabels(const fs::path & file, TLabel label, double shiftInMillimetres = 0.0)
{
  auto image = TImage::New();
  image->SetRegions(itk::Size<3>{ { 16, 16, 12 } });
  const double spacing[3] = { 1.0, 1.0, 1.5 };
  const double origin[3] = { -7.5 + shiftInMillimetres, -7.5, -8.25 };
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->Allocate();
  for (unsigned z = 0; z < 12; ++z)
  {
    for (unsigned y = 0; y < 16; ++y)
    {
      for (unsigned x = 0; x < 16; ++x)
      {
        image->SetPixel({ { x, y, z } }, static_cast<typename TImage::PixelType>(label(x)));
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
           const Orientation & orientation,
           const std::string & imageType)
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
  set("0008|0008", imageType);
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
            const std::string &            prefix = "IM",
            const std::string &            imageType = "ORIGINAL\\PRIMARY\\AXIAL")
{
  std::vector<std::string> files;
  for (size_t i = 0; i < slices.size(); ++i)
  {
    char name[64];
    std::snprintf(name, sizeof(name), "%s%04zu.dcm", prefix.c_str(), i + 1);
    const fs::path file = directory / name;
    WriteSlice(file, seriesUID, static_cast<unsigned>(i + 1), slices[i].position, slices[i].orientation, imageType);
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

/** A data element of a string VR, padded to an even length as DICOM wants (UI with a NUL, the others a space). */
gdcm::DataElement
MakeElement(const gdcm::Tag & tag, const gdcm::VR::VRType vr, const std::string & value)
{
  gdcm::DataElement element(tag);
  element.SetVR(vr);
  std::string padded = value;
  if (padded.size() % 2)
  {
    padded.push_back(vr == gdcm::VR::UI ? '\0' : ' ');
  }
  element.SetByteValue(padded.data(), static_cast<uint32_t>(padded.size()));
  return element;
}

/** A DICOM object without pixel data (a Basic Text SR, as a dose report stored beside the slices). */
void
WriteReport(const fs::path & file, const std::string & seriesUID, const std::string & instanceUID)
{
  gdcm::Writer    writer;
  gdcm::File &    dicom = writer.GetFile();
  gdcm::DataSet & dataSet = dicom.GetDataSet();
  dataSet.Insert(
    MakeElement(gdcm::Tag(0x0008, 0x0016), gdcm::VR::UI, "1.2.840.10008.5.1.4.1.1.88.11")); // Basic Text SR
  dataSet.Insert(MakeElement(gdcm::Tag(0x0008, 0x0018), gdcm::VR::UI, instanceUID));
  dataSet.Insert(MakeElement(gdcm::Tag(0x0008, 0x0060), gdcm::VR::CS, "SR"));
  dataSet.Insert(MakeElement(gdcm::Tag(0x0010, 0x0010), gdcm::VR::PN, "PBDRR^TEST"));
  dataSet.Insert(MakeElement(gdcm::Tag(0x0020, 0x000d), gdcm::VR::UI, studyUID));
  dataSet.Insert(MakeElement(gdcm::Tag(0x0020, 0x000e), gdcm::VR::UI, seriesUID));
  dataSet.Insert(MakeElement(gdcm::Tag(0x0040, 0xa040), gdcm::VR::CS, "CONTAINER"));
  dicom.GetHeader().SetDataSetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  writer.SetCheckFileMetaInformation(true);
  writer.SetFileName(file.string().c_str());
  if (!writer.Write())
  {
    throw std::runtime_error("cannot write the DICOM report " + file.string());
  }
}

/** A DICOM media storage directory as scanners write beside their slices (a DICOMDIR, or Philips' DIRFILE): the
 * SOP class in the file meta information only, a file-set ID and a directory record sequence (left empty). */
void
WriteDicomDirectory(const fs::path & file)
{
  gdcm::Writer    writer;
  gdcm::File &    dicom = writer.GetFile();
  gdcm::DataSet & dataSet = dicom.GetDataSet();
  dataSet.Insert(MakeElement(gdcm::Tag(0x0004, 0x1130), gdcm::VR::CS, "PBDRRTEST"));
  gdcm::SmartPointer<gdcm::SequenceOfItems> records = new gdcm::SequenceOfItems;
  records->SetLengthToUndefined();
  gdcm::DataElement sequence(gdcm::Tag(0x0004, 0x1220));
  sequence.SetVR(gdcm::VR::SQ);
  sequence.SetValue(*records);
  sequence.SetVLToUndefined();
  dataSet.Insert(sequence);
  gdcm::FileMetaInformation & meta = dicom.GetHeader();
  meta.Insert(MakeElement(gdcm::Tag(0x0002, 0x0002), gdcm::VR::UI, "1.2.840.10008.1.3.10"));
  meta.Insert(MakeElement(gdcm::Tag(0x0002, 0x0003), gdcm::VR::UI, studyUID + ".999"));
  meta.SetDataSetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  writer.SetCheckFileMetaInformation(true);
  writer.SetFileName(file.string().c_str());
  if (!writer.Write())
  {
    throw std::runtime_error("cannot write the DICOM directory " + file.string());
  }
}

/** A CT localizer as a scanner writes it (the Philips surview of ../shared/data has this header): 32 columns x 24 rows
 * at 1 mm in the isocenter plane x = 0, centred on the phantom, columns along +y and rows along -z (a lateral view),
 * source 570 mm from the patient and 1040 mm from the detector. `edit` changes the data set before it is written. */
void
WriteLocalizer(const fs::path & file, const std::function<void(gdcm::DataSet &)> & edit = {})
{
  gdcm::Writer    writer;
  gdcm::File &    dicom = writer.GetFile();
  gdcm::DataSet & dataSet = dicom.GetDataSet();
  const auto      text = [&](uint16_t group, uint16_t element, gdcm::VR::VRType vr, const std::string & value) {
    dataSet.Insert(MakeElement(gdcm::Tag(group, element), vr, value));
  };
  text(0x0008, 0x0008, gdcm::VR::CS, "ORIGINAL\\PRIMARY\\LOCALIZER");
  text(0x0008, 0x0016, gdcm::VR::UI, "1.2.840.10008.5.1.4.1.1.2");
  text(0x0008, 0x0018, gdcm::VR::UI, studyUID + ".77.1");
  text(0x0008, 0x0060, gdcm::VR::CS, "CT");
  text(0x0018, 0x1110, gdcm::VR::DS, "1040");
  text(0x0018, 0x1111, gdcm::VR::DS, "570");
  text(0x0018, 0x1141, gdcm::VR::DS, "90");
  text(0x0020, 0x000d, gdcm::VR::UI, studyUID);
  text(0x0020, 0x000e, gdcm::VR::UI, studyUID + ".77");
  text(0x0020, 0x0032, gdcm::VR::DS, "0\\-15.5\\11.5");
  text(0x0020, 0x0037, gdcm::VR::DS, "0\\1\\0\\0\\0\\-1");
  text(0x0028, 0x0004, gdcm::VR::CS, "MONOCHROME2");
  text(0x0028, 0x0030, gdcm::VR::DS, "1\\1");
  const auto unsignedShort = [&](uint16_t element, uint16_t value) {
    gdcm::DataElement e(gdcm::Tag(0x0028, element));
    e.SetVR(gdcm::VR::US);
    e.SetByteValue(reinterpret_cast<const char *>(&value), 2);
    dataSet.Insert(e);
  };
  unsignedShort(0x0002, 1);
  unsignedShort(0x0010, 24);
  unsignedShort(0x0011, 32);
  unsignedShort(0x0100, 16);
  unsignedShort(0x0101, 16);
  unsignedShort(0x0102, 15);
  unsignedShort(0x0103, 0);
  std::vector<uint16_t> pixels(32 * 24, 1000);
  gdcm::DataElement     pixelData(gdcm::Tag(0x7fe0, 0x0010));
  pixelData.SetVR(gdcm::VR::OW);
  pixelData.SetByteValue(reinterpret_cast<const char *>(pixels.data()), static_cast<uint32_t>(pixels.size() * 2));
  dataSet.Insert(pixelData);
  if (edit)
  {
    edit(dataSet);
  }
  dicom.GetHeader().SetDataSetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  writer.SetCheckFileMetaInformation(true);
  writer.SetFileName(file.string().c_str());
  if (!writer.Write())
  {
    throw std::runtime_error("cannot write the DICOM localizer " + file.string());
  }
}

/** Projection matrix files: a view (gantry 30, 16 x 16 at 4 mm, mirrored) as a geometry file and as a matrix, and
 * matrices that are not one: two rows, a row of 3, a NaN, singular, skewed. */
void
WriteProjectionMatrices(const fs::path & root)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetGantryAngleInDegrees(30.0);
  geometry->SetDetectorSize({ { 16, 16 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(4.0));
  geometry->SetColumnsMirrored(true);
  geometry->VerifyGeometry();
  itk::DRRProjectionGeometryFileIO::Pointer geometryWriter = itk::DRRProjectionGeometryFileIO::New();
  geometryWriter->SetFileName((root / "matrix_view.txt").string());
  geometryWriter->Write(geometry);
  const auto matrix = geometry->GetProjectionMatrix();
  auto       matrixWriter = itk::DRRProjectionMatrixFileIO::New();
  matrixWriter->SetFileName((root / "matrix_view.P.txt").string());
  matrixWriter->Write(matrix);
  std::ostringstream rows;
  itk::DRRProjectionMatrixFileIO::WriteToStream(rows, matrix);
  const std::string good = rows.str();
  WriteText(root / "matrix_two_rows.txt", good.substr(0, good.find('\n', good.find('\n') + 1) + 1));
  WriteText(root / "matrix_row_of_3.txt", "1 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  WriteText(root / "matrix_nan.txt", "# a NaN\n1 0 0 0\n0 nan 0 0\n0 0 1 10\n");
  WriteText(root / "matrix_singular.txt", "1 2 3 4\n2 4 6 8\n0 0 1 100\n");
  WriteText(root / "matrix_skewed.txt", "1000 300 0 0\n0 1000 0 0\n0 0 1 500\n");
}

/** The value of the multi-frame phantom: the series phantom, plus a marker in its first three slices, so that a
 * volume read upside down differs. */
short
MultiFrameValue(unsigned x, unsigned y, unsigned z)
{
  return static_cast<short>(PhantomValue(0.9 * (x - 7.5), 0.9 * (y - 7.5)) + (z < 3 && x < 4 ? 500 : 0));
}

/** A multi-frame (enhanced CT) DICOM file of 16 x 16 x 8 voxels at 0.9 x 0.9 x 2.5 mm, origin (-6.75, -6.75, -10),
 * frames stored from the lowest position up, or, with `descending`, from the highest down (then its per-frame
 * positions are rewritten to say so). */
void
WriteMultiFrame(const fs::path & file, const std::string & seriesUID, bool descending = false)
{
  using ImageType = itk::Image<short, 3>;
  const auto image = MakeShortVolume(
    { { 16, 16, 8 } }, { { 0.9, 0.9, 2.5 } }, { { -6.75, -6.75, -10.0 } }, [&](unsigned x, unsigned y, unsigned z) {
      return MultiFrameValue(x, y, descending ? 7 - z : z);
    });
  auto io = itk::GDCMImageIO::New();
  io->KeepOriginalUIDOn();
  itk::MetaDataDictionary dictionary;
  itk::EncapsulateMetaData<std::string>(dictionary, "0008|0016", "1.2.840.10008.5.1.4.1.1.2");
  itk::EncapsulateMetaData<std::string>(dictionary, "0008|0018", seriesUID + ".1");
  itk::EncapsulateMetaData<std::string>(dictionary, "0008|0060", "CT");
  itk::EncapsulateMetaData<std::string>(dictionary, "0020|000d", studyUID);
  itk::EncapsulateMetaData<std::string>(dictionary, "0020|000e", seriesUID);
  io->SetMetaDataDictionary(dictionary);
  image->SetMetaDataDictionary(dictionary);
  auto writer = itk::ImageFileWriter<ImageType>::New();
  writer->SetInput(image);
  writer->SetImageIO(io);
  writer->SetFileName(file.string());
  writer->Update();
}

/** Rewrites a multi-frame file in place: positions(k) gives frame k's Image Position (Patient); with
 * `dropPositions` the functional groups are removed instead and the geometry written as top-level elements, with
 * `topLevelSpacing` (if not empty) as the Spacing Between Slices. */
void
EditFrames(const fs::path &                               file,
           const std::function<Vector3(unsigned frame)> & positions,
           bool                                           dropPositions = false,
           const std::string &                            topLevelSpacing = "",
           bool                                           legacyClass = false)
{
  gdcm::Reader reader;
  reader.SetFileName(file.string().c_str());
  if (!reader.Read())
  {
    throw std::runtime_error("cannot read back " + file.string());
  }
  gdcm::DataSet & dataSet = reader.GetFile().GetDataSet();
  const gdcm::Tag perFrameTag(0x5200, 0x9230), sharedTag(0x5200, 0x9229);
  if (dropPositions)
  {
    // A legacy multi-frame object: no functional groups, the geometry in top-level elements.
    dataSet.Remove(perFrameTag);
    dataSet.Remove(sharedTag);
    dataSet.Replace(MakeElement(gdcm::Tag(0x0020, 0x0032), gdcm::VR::DS, "-6.75\\-6.75\\-10"));
    dataSet.Replace(MakeElement(gdcm::Tag(0x0020, 0x0037), gdcm::VR::DS, "1\\0\\0\\0\\1\\0"));
    dataSet.Replace(MakeElement(gdcm::Tag(0x0028, 0x0030), gdcm::VR::DS, "0.9\\0.9"));
    if (!topLevelSpacing.empty())
    {
      dataSet.Replace(MakeElement(gdcm::Tag(0x0018, 0x0088), gdcm::VR::DS, topLevelSpacing));
    }
    if (legacyClass)
    {
      // CT Image Storage, not Enhanced CT.
      dataSet.Replace(MakeElement(gdcm::Tag(0x0008, 0x0016), gdcm::VR::UI, "1.2.840.10008.5.1.4.1.1.2"));
      reader.GetFile().GetHeader().Clear();
    }
  }
  else
  {
    gdcm::DataElement                         perFrame = dataSet.GetDataElement(perFrameTag);
    gdcm::SmartPointer<gdcm::SequenceOfItems> frames = perFrame.GetValueAsSQ();
    for (unsigned k = 0; k < frames->GetNumberOfItems(); ++k)
    {
      gdcm::DataSet &                           groups = frames->GetItem(k + 1).GetNestedDataSet();
      gdcm::DataElement                         plane = groups.GetDataElement(gdcm::Tag(0x0020, 0x9113));
      gdcm::SmartPointer<gdcm::SequenceOfItems> planeItems = plane.GetValueAsSQ();
      const Vector3                             position = positions(k);
      planeItems->GetItem(1).GetNestedDataSet().Replace(
        MakeElement(gdcm::Tag(0x0020, 0x0032), gdcm::VR::DS, Join(position.data(), 3)));
      plane.SetValue(*planeItems);
      plane.SetVLToUndefined();
      groups.Replace(plane);
    }
    perFrame.SetValue(*frames);
    perFrame.SetVLToUndefined();
    dataSet.Replace(perFrame);
  }
  gdcm::Writer writer;
  writer.SetFile(reader.GetFile());
  writer.SetFileName(file.string().c_str());
  if (!writer.Write())
  {
    throw std::runtime_error("cannot rewrite " + file.string());
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

/** The bytes of file. */
std::string
ReadFileBytes(const fs::path & file)
{
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/** The fault matrix's inputs (issue 39), in folder: the phantom in every volume format pbdrr reads, FORMAT_CUT.EXT with
 * the file that holds its pixels (the file itself, or the data file beside a .mhd or .nhdr header) cut to a third, to
 * two thirds and by its last byte; promise.mha and promise.nii, headers that promise a slice more than their data;
 * and a 32 x 32 X-ray (for geometry_32.txt), whole (xray_whole.mha) and in three formats cut to two thirds
 * (xray_FORMAT.EXT). Each format has its
 * own stem: NIfTI's reader, given a.nii.gz, opens a.nii if there is one. */
void
WriteFaultMatrix(const fs::path & folder)
{
  FreshDirectory(folder);
  struct Format
  {
    const char * Tag;
    const char * Extension;
    bool         Compress;
    const char * DataExtension; // the pixels' own file beside the header, or ""
  };
  const Format formats[] = { { "mha", "mha", false, "" },    { "zmha", "mha", true, "" },
                             { "mhd", "mhd", false, "raw" }, { "nrrd", "nrrd", false, "" },
                             { "gznrrd", "nrrd", true, "" }, { "nhdr", "nhdr", false, "raw" },
                             { "nii", "nii", false, "" },    { "niigz", "nii.gz", true, "" },
                             { "tif", "tif", false, "" } };
  const auto   phantom = MakeShortVolume(
    { { 16, 16, 12 } }, { { 1.0, 1.0, 1.5 } }, { { -7.5, -7.5, -8.25 } }, [](unsigned x, unsigned y, unsigned z) {
      return static_cast<short>(PhantomValue(x - 7.5, y - 7.5) + 7 * z);
    });
  for (const Format & format : formats)
  {
    for (const char * cut : { "third", "two_thirds", "last_byte" })
    {
      const std::string stem = std::string(format.Tag) + "_" + cut;
      const fs::path    file = folder / (stem + "." + format.Extension);
      itk::WriteImage(phantom, file.string(), format.Compress);
      const fs::path data = *format.DataExtension ? folder / (stem + "." + format.DataExtension) : file;
      const auto     size = fs::file_size(data);
      fs::resize_file(data,
                      std::string(cut) == "third"        ? size / 3
                      : std::string(cut) == "two_thirds" ? size * 2 / 3
                                                         : size - 1);
    }
  }
  // Headers that promise 13 slices over the data of 12.
  const fs::path meta = folder / "promise.mha";
  itk::WriteImage(phantom, meta.string());
  std::string  bytes = ReadFileBytes(meta);
  const size_t dims = bytes.find("DimSize = 16 16 12");
  if (dims == std::string::npos)
  {
    throw std::runtime_error("promise.mha: no DimSize line");
  }
  bytes.replace(dims, 18, "DimSize = 16 16 13");
  WriteText(meta, bytes);
  const fs::path nifti = folder / "promise.nii";
  itk::WriteImage(phantom, nifti.string());
  bytes = ReadFileBytes(nifti);
  bytes[46] = 13; // dim[3], a little-endian short at byte 46 of a NIfTI-1 header
  WriteText(nifti, bytes);
  // The X-rays.
  auto xray = itk::Image<float, 2>::New();
  xray->SetRegions(itk::Size<2>{ { 32, 32 } });
  xray->Allocate();
  for (size_t k = 0; k < 32 * 32; ++k)
  {
    xray->GetBufferPointer()[k] = static_cast<float>(k % 32) * 0.01f + static_cast<float>(k / 32) * 0.02f;
  }
  itk::WriteImage(xray, (folder / "xray_whole.mha").string()); // the X-ray of the CTs' register cases
  for (const char * extension : { "mha", "nii", "tif" })
  {
    const fs::path file = folder / (std::string("xray_") + extension + "." + extension);
    itk::WriteImage(xray, file.string());
    fs::resize_file(file, fs::file_size(file) * 2 / 3);
  }
}

int
main(int argc, char * argv[])
{
  if (argc != 2 && argc != 3)
  {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIRECTORY [JPEG2000_DICOM_DIRECTORY]" << std::endl;
    return 2;
  }
  try
  {
    const fs::path root = argv[1];
    fs::create_directories(root);

    // Volume files.
    WritePhantom(root / "phantom.mha");
    // Label images on the phantom's grid: 1 on the left half, 2 on the right, 0 on the outer columns; and bad ones.
    WriteLabels<itk::Image<unsigned char, 3>>(root / "labels.mha",
                                              [](unsigned x) { return x == 0 || x == 15 ? 0 : 1 + x / 8; });
    WriteLabels<itk::Image<float, 3>>(root / "labels_float.mha", [](unsigned x) { return 1.0f + x / 8; });
    WriteLabels<itk::Image<short, 3>>(root / "labels_negative.mha", [](unsigned x) { return x == 3 ? -1 : 1; });
    WriteConstant<itk::Image<unsigned char, 2>>(root / "labels_2d.mha", { { 16, 16 } }, 1);
    WriteLabels<itk::Image<unsigned char, 3>>(
      root / "labels_elsewhere.mha", [](unsigned) { return 1; }, 500.0); // another volume's
    // For pbdrr register: no symmetry, so that every pose parameter shows (three bone blocks in a soft-tissue box).
    itk::WriteImage(MakeShortVolume({ { 24, 20, 16 } },
                                    { { 2.0, 2.0, 2.0 } },
                                    { { -23.0, -19.0, -15.0 } },
                                    [](unsigned x, unsigned y, unsigned z) {
                                      const bool a = x >= 3 && x < 9 && y >= 4 && y < 12 && z >= 5 && z < 13;
                                      const bool b = x >= 13 && x < 20 && y >= 13 && y < 17 && z >= 2 && z < 7;
                                      const bool c = x >= 16 && x < 21 && y >= 3 && y < 8 && z >= 10 && z < 14;
                                      return static_cast<short>(a || b || c ? 1200 : 40);
                                    }),
                    (root / "register_phantom.mha").string());
    WriteConstant<itk::Image<short, 2>>(root / "image2d.mha", { { 16, 16 } }, 0);
    WriteConstant<itk::Image<short, 4>>(root / "image4d.mha", { { 4, 4, 4, 2 } }, 0);
    WriteConstant<itk::Image<itk::Vector<float, 3>, 3>>(
      root / "vector.mha", { { 8, 8, 8 } }, itk::Vector<float, 3>(0.0f));
    WriteText(root / "garbage.mha", "this is not an image\nNDims = banana\n");
    WritePhantom(root / "truncated.mha");
    fs::resize_file(root / "truncated.mha", fs::file_size(root / "truncated.mha") - 1000);
    FreshDirectory(root / "isdir.mha");
    WriteFaultMatrix(root / "faults");

    // Geometry files.
    WriteText(root / "geometry_32.txt",
              "# a 32 x 32 detector\nprojection perspective\nsad 1000\nsid 1500\ngantry 90\ncols 32\nrows 32\n"
              "spacing 1.2 1.2\n");
    WriteText(root / "geometry_badkey.txt", "sad 1000\nfrobnicate 3\n");
    WriteText(root / "geometry_badvalue.txt", "sad 1000\nsid 1500\ncols many\n");
    WriteText(root / "geometry_missing_value.txt", "sad 1000\nsid\n");
    WriteText(root / "geometry_not_a_number.txt", "sad 1000\nsid far\n");
    WriteText(root / "geometry_vup_parallel.txt", "# the detector has no rows\nnrm 0 0 1\nvup 0 0 -2\n");
    WriteText(root / "geometry_negative_size.txt", "cols 32\nrows -32\n");
    WriteText(root / "geometry_negative_spacing.txt", "spacing 1.2 -1.2\n");
    WriteText(root / "geometry_binary.txt", std::string("sad \0\x01\xff 1000\n", 12));

    // Voxels that are not numbers, an image without voxels, and float HU at and beyond the scanners' extremes.
    using FloatVolume = itk::Image<float, 3>;
    for (const auto & bad : { std::make_pair("nan", std::numeric_limits<float>::quiet_NaN()),
                              std::make_pair("inf", std::numeric_limits<float>::infinity()) })
    {
      auto image = FloatVolume::New();
      image->SetRegions(FloatVolume::SizeType{ { 8, 8, 8 } });
      image->Allocate();
      image->FillBuffer(0.0f);
      image->SetPixel({ { 2, 3, 4 } }, bad.second);
      itk::WriteImage(image, (root / (std::string(bad.first) + ".mha")).string());
    }
    WriteText(root / "empty.mha",
              "ObjectType = Image\nNDims = 3\nDimSize = 4 4 0\nElementType = MET_SHORT\nElementDataFile = LOCAL\n");
    {
      auto image = FloatVolume::New();
      image->SetRegions(FloatVolume::SizeType{ { 8, 8, 8 } });
      image->Allocate();
      const float extremes[] = { -1e30f, -32768.0f, -3024.0f, -2048.0f, -1024.0f, 3071.0f, 32767.0f, 1e6f };
      float *     buffer = image->GetBufferPointer();
      for (size_t v = 0; v < 512; ++v)
      {
        buffer[v] = extremes[(v * 5 + v / 8) % 8];
      }
      itk::WriteImage(image, (root / "float_extremes.mha").string());
    }

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
    std::vector<SliceSpec> tiltUneven = tilt;
    tiltUneven[6].position[1] += 0.3; // the drift changes between slices 5, 6 and 7: not one tilted grid
    WriteSeries(FreshDirectory(root / "dicom_tilt_uneven"), uid + "23", tiltUneven);

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

    // A slice cut short in the middle of a good series.
    const fs::path truncated = FreshDirectory(root / "dicom_truncated");
    WriteSeries(truncated, uid + "8", AxialStack(8, 2.5));
    fs::resize_file(truncated / "IM0005.dcm", fs::file_size(truncated / "IM0005.dcm") * 3 / 5);

    // Non-image objects beside the slices: a report in the same series and one in a series of its own.
    const fs::path report = FreshDirectory(root / "dicom_with_report");
    WriteSeries(report, uid + "9", AxialStack(8, 2.5));
    WriteReport(report / "SR0001.dcm", uid + "9", uid + "9.100");
    WriteReport(report / "SR0002.dcm", uid + "10", uid + "10.1");

    // A scanner export: the slices with the export's media storage directory beside them (Philips names it DIRFILE).
    const fs::path exported = FreshDirectory(root / "dicom_with_dirfile");
    WriteSeries(exported, uid + "9", AxialStack(8, 2.5));
    WriteDicomDirectory(exported / "DIRFILE");

    // A whole export: its DIRFILE at the root, and in folders below it a localizer series (12 single-slice files: the
    // most files, never a volume), the volume (8 slices) and a smaller series (5), each beside its own DIRFILE.
    const fs::path exportRoot = FreshDirectory(root / "dicom_export");
    WriteDicomDirectory(exportRoot / "DIRFILE");
    const std::vector<std::pair<std::string, std::string>> folders = { { "S1000", "20" },
                                                                       { "S2010", "21" },
                                                                       { "S3010", "22" } };
    for (const auto & [folder, number] : folders)
    {
      const fs::path directory = FreshDirectory(exportRoot / folder);
      WriteDicomDirectory(directory / "DIRFILE");
      if (number == "20")
      {
        WriteSeries(directory, uid + number, AxialStack(12, 2.5), "I", "ORIGINAL\\PRIMARY\\LOCALIZER");
      }
      else
      {
        WriteSeries(directory, uid + number, AxialStack(number == "21" ? 8 : 5, 2.5), "I");
      }
    }

    // CT localizers: good, and a header that is not one pbdrr can render on.
    WriteLocalizer(root / "localizer_lateral.dcm");
    WriteLocalizer(root / "localizer_table_along_columns.dcm", [](gdcm::DataSet & d) {
      d.Replace(MakeElement(gdcm::Tag(0x0020, 0x0037), gdcm::VR::DS, "0\\0\\-1\\0\\1\\0"));
    });
    WriteLocalizer(root / "localizer_no_distances.dcm", [](gdcm::DataSet & d) { d.Remove(gdcm::Tag(0x0018, 0x1110)); });
    WriteLocalizer(root / "localizer_detector_inside.dcm",
                   [](gdcm::DataSet & d) { d.Replace(MakeElement(gdcm::Tag(0x0018, 0x1110), gdcm::VR::DS, "500")); });
    WriteLocalizer(root / "localizer_axial.dcm", [](gdcm::DataSet & d) {
      d.Replace(MakeElement(gdcm::Tag(0x0008, 0x0008), gdcm::VR::CS, "ORIGINAL\\PRIMARY\\AXIAL"));
    });
    WriteProjectionMatrices(root);

    // Multi-frame files: good (frames stored upwards and downwards; a legacy object placed by its top-level spacing),
    // and with frame positions that are uneven, out of order, absent from an enhanced object, or absent with no
    // spacing at all.
    const auto framePosition = [](double z) { return Vector3{ { -6.75, -6.75, z } }; };
    WriteMultiFrame(FreshDirectory(root / "dicom_multiframe") / "MF0001.dcm", uid + "11");
    // The fault matrix's multi-frame file, its pixel data cut to two thirds of the file.
    const fs::path cutFrames = FreshDirectory(root / "faults" / "multiframe_cut") / "MF0001.dcm";
    fs::copy_file(root / "dicom_multiframe" / "MF0001.dcm", cutFrames);
    fs::resize_file(cutFrames, fs::file_size(cutFrames) * 2 / 3);
    const fs::path descending = FreshDirectory(root / "dicom_multiframe_descending") / "MF0001.dcm";
    WriteMultiFrame(descending, uid + "12", true);
    EditFrames(descending, [&](unsigned k) { return framePosition(7.5 - 2.5 * k); });
    const fs::path unevenFrames = FreshDirectory(root / "dicom_multiframe_uneven") / "MF0001.dcm";
    WriteMultiFrame(unevenFrames, uid + "13");
    EditFrames(unevenFrames, [&](unsigned k) { return framePosition(-10.0 + 2.5 * k + (k >= 5 ? 0.6 : 0.0)); });
    const fs::path shuffled = FreshDirectory(root / "dicom_multiframe_shuffled") / "MF0001.dcm";
    WriteMultiFrame(shuffled, uid + "14");
    EditFrames(shuffled, [&](unsigned k) { return framePosition(-10.0 + 2.5 * (k == 2 ? 5 : (k == 5 ? 2 : k))); });
    const fs::path legacy = FreshDirectory(root / "dicom_multiframe_legacy") / "MF0001.dcm";
    WriteMultiFrame(legacy, uid + "15");
    EditFrames(legacy, nullptr, true, "2.5", true);
    const fs::path noGroups = FreshDirectory(root / "dicom_multiframe_nogroups") / "MF0001.dcm";
    WriteMultiFrame(noGroups, uid + "17");
    EditFrames(noGroups, nullptr, true, "2.5");
    const fs::path nowhere = FreshDirectory(root / "dicom_multiframe_nowhere") / "MF0001.dcm";
    WriteMultiFrame(nowhere, uid + "16");
    EditFrames(nowhere, nullptr, true);

    // Real JPEG 2000 slices, one of them cut short (only if the shared data is there).
    if (argc > 2 && fs::is_directory(argv[2]))
    {
      const fs::path        cut = FreshDirectory(root / "dicom_jpeg2000_truncated");
      std::vector<fs::path> slices;
      for (const auto & entry : fs::directory_iterator(argv[2]))
      {
        slices.push_back(entry.path());
      }
      std::sort(slices.begin(), slices.end());
      for (const auto & slice : slices)
      {
        fs::copy_file(slice, cut / slice.filename());
      }
      const fs::path victim = cut / slices[slices.size() / 2].filename();
      fs::resize_file(victim, fs::file_size(victim) - 5000);
    }

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
