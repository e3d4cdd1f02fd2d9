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
// pbdrr's parallel DICOM slice reader against itk::ImageSeriesReader, which it replaces: the same geometry and the same
// voxels, bit for bit, on one thread and on several, for the test series, for slices rewritten to every way of storing
// values it decodes (12 bits with junk in the unused bits, signed and unsigned, rescaled to int16 or to double, 8
// bits), and for the real series of ../shared/data (skipped when absent).
#include "pbdrrDicomSeriesDiscovery.h"
#include "pbdrrDicomSliceReader.h"
#include "pbdrrGdcmWarningCapture.h"

#include "gdcmReader.h"
#include "gdcmWriter.h"
#include "itkGDCMImageIO.h"
#include "itkImageSeriesReader.h"
#include "itkMetaDataObject.h"
#include "itkPlatformMultiThreader.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace
{
namespace fs = std::filesystem;

/** The inputs MakeTestVolumes writes (the pbdrrData fixture). */
fs::path
TestData()
{
  return PBDRR_TEST_DATA_DIR;
}

fs::path
SharedData()
{
  return PBDRR_SHARED_DATA_DIR;
}

/** The .dcm files of a directory, sorted by name (the test series are named in slice order). */
std::vector<std::string>
SliceFiles(const fs::path & directory)
{
  std::vector<std::string> files;
  for (const auto & entry : fs::directory_iterator(directory))
  {
    if (entry.path().extension() == ".dcm")
    {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/** The files of the largest series of a directory, in the order pbdrr reads them. */
std::vector<std::string>
SeriesFiles(const fs::path & directory)
{
  pbdrr::GdcmWarningCapture quiet;
  const auto                list = pbdrr::FindDicomSeries(directory.string());
  std::vector<std::string>  files;
  for (const auto & series : list.Series)
  {
    files = series.Files.size() > files.size() ? series.Files : files;
  }
  return files;
}

template <typename TVolume>
typename TVolume::Pointer
ReadWithSeriesReader(const std::vector<std::string> & files, bool forceOrthogonalDirection)
{
  auto reader = itk::ImageSeriesReader<TVolume>::New();
  reader->SetImageIO(itk::GDCMImageIO::New());
  reader->SetFileNames(files);
  reader->SetForceOrthogonalDirection(forceOrthogonalDirection);
  reader->Update();
  return reader->GetOutput();
}

/** The same grid, dictionary entry and voxels, compared exactly. */
template <typename TVolume>
void
ExpectSameVolume(const TVolume & expected, const TVolume & actual, const std::string & what)
{
  ASSERT_EQ(actual.GetLargestPossibleRegion(), expected.GetLargestPossibleRegion()) << what;
  ASSERT_EQ(actual.GetBufferedRegion(), expected.GetBufferedRegion()) << what;
  EXPECT_EQ(actual.GetOrigin(), expected.GetOrigin()) << what;
  EXPECT_EQ(actual.GetSpacing(), expected.GetSpacing()) << what;
  EXPECT_EQ(actual.GetDirection(), expected.GetDirection()) << what;
  const char * key = "ITK_non_uniform_sampling_deviation";
  double       expectedDeviation = -1.0, actualDeviation = -1.0;
  EXPECT_EQ(itk::ExposeMetaData(actual.GetMetaDataDictionary(), key, actualDeviation),
            itk::ExposeMetaData(expected.GetMetaDataDictionary(), key, expectedDeviation))
    << what;
  EXPECT_EQ(actualDeviation, expectedDeviation) << what;
  const size_t voxels = expected.GetBufferedRegion().GetNumberOfPixels();
  const auto * a = actual.GetBufferPointer();
  const auto * e = expected.GetBufferPointer();
  size_t       different = 0, first = voxels;
  for (size_t v = 0; v < voxels; ++v)
  {
    // Bytes, not values: a NaN equals itself, and -0 is not 0.
    if (std::memcmp(a + v, e + v, sizeof(*a)) != 0)
    {
      first = std::min(first, v);
      ++different;
    }
  }
  EXPECT_EQ(different, 0u) << what << ": " << different << " of " << voxels << " voxels differ, the first at offset "
                           << first << " (" << (first < voxels ? +a[first] : 0) << " instead of "
                           << (first < voxels ? +e[first] : 0) << ")";
}

/** Reads `files` with ImageSeriesReader and with ReadDicomSlices on 1, 2 and 5 threads, and compares; each parallel
 * read reports every file once, in count order. */
template <typename TVolume>
void
ExpectSameAsSeriesReader(const std::vector<std::string> & files,
                         bool                             forceOrthogonalDirection,
                         const std::string &              what)
{
  ASSERT_GE(files.size(), 2u) << what;
  pbdrr::GdcmWarningCapture quiet; // GDCM's warnings about the real series' private tags, from several threads
  const auto                expected = ReadWithSeriesReader<TVolume>(files, forceOrthogonalDirection);
  for (const unsigned int threads : { 1u, 2u, 5u })
  {
    auto threader = itk::PlatformMultiThreader::New();
    threader->SetMaximumNumberOfThreads(threads);
    threader->SetNumberOfWorkUnits(threads);
    size_t reported = 0;
    bool   inOrder = true;
    auto   progress = [&](size_t read, size_t total) {
      inOrder = inOrder && read == reported + 1 && total == files.size();
      reported = read;
    };
    const auto        actual = pbdrr::ReadDicomSlices<TVolume>(files, forceOrthogonalDirection, progress, threader);
    const std::string on = what + " on " + std::to_string(threads) + " thread(s)";
    ASSERT_NE(actual, nullptr) << on << ": left to ImageSeriesReader";
    ExpectSameVolume(*expected, *actual, on);
    EXPECT_TRUE(inOrder) << on;
    EXPECT_EQ(reported, files.size()) << on;
  }
}

/** A slice's values stored another way: the pixel data (as 16-bit words) and the pixel module's tags. */
struct Storage
{
  std::function<uint16_t(int16_t value, size_t slice, size_t pixel)> Word;
  uint16_t                                                           BitsAllocated{ 16 };
  uint16_t                                                           BitsStored{ 16 };
  uint16_t                                                           PixelRepresentation{ 1 };
  std::string                                                        Intercept{ "0" };
  std::string                                                        Slope{ "1" };
  std::string                                                        Photometric{ "MONOCHROME2" };
};

/** Junk in the bits above Bits Stored (overlays, or a scanner's leftovers): a reader must clear it. */
uint16_t
Junk(size_t slice, size_t pixel, uint16_t bitsStored)
{
  const auto hash = static_cast<uint32_t>((slice * 977 + pixel) * 2654435761u);
  return static_cast<uint16_t>((hash >> 16) << bitsStored);
}

void
SetValue(gdcm::DataSet & dataSet, uint16_t group, uint16_t element, const gdcm::VR & vr, std::string bytes)
{
  if (bytes.size() % 2 != 0)
  {
    bytes += vr == gdcm::VR::UI ? '\0' : ' ';
  }
  gdcm::DataElement value(gdcm::Tag(group, element));
  value.SetVR(vr);
  value.SetByteValue(bytes.data(), static_cast<uint32_t>(bytes.size()));
  dataSet.Replace(value);
}

std::string
Word(uint16_t value)
{
  return std::string(reinterpret_cast<const char *>(&value), 2);
}

/** Copies the slices `files` into `directory`, their values stored as `storage` says (each slice's values shifted by
 * 7 x its index, so that no two slices are alike). Returns the copies, in the same order. */
std::vector<std::string>
WriteStoredAs(const std::vector<std::string> & files, const fs::path & directory, const Storage & storage)
{
  fs::remove_all(directory);
  fs::create_directories(directory);
  std::vector<std::string> copies;
  for (size_t slice = 0; slice < files.size(); ++slice)
  {
    gdcm::Reader reader;
    reader.SetFileName(files[slice].c_str());
    EXPECT_TRUE(reader.Read()) << files[slice];
    gdcm::DataSet &         dataSet = reader.GetFile().GetDataSet();
    const gdcm::ByteValue * pixels = dataSet.GetDataElement(gdcm::Tag(0x7fe0, 0x0010)).GetByteValue();
    std::vector<int16_t>    values(pixels->GetLength() / 2);
    std::memcpy(values.data(), pixels->GetPointer(), values.size() * 2);
    std::string words;
    for (size_t p = 0; p < values.size(); ++p)
    {
      const std::string word = Word(storage.Word(static_cast<int16_t>(values[p] + 7 * slice), slice, p));
      words += storage.BitsAllocated == 8 ? word.substr(0, 1) : word;
    }
    SetValue(dataSet, 0x7fe0, 0x0010, storage.BitsAllocated == 8 ? gdcm::VR::OB : gdcm::VR::OW, words);
    SetValue(dataSet, 0x0028, 0x0100, gdcm::VR::US, Word(storage.BitsAllocated));
    SetValue(dataSet, 0x0028, 0x0101, gdcm::VR::US, Word(storage.BitsStored));
    SetValue(dataSet, 0x0028, 0x0102, gdcm::VR::US, Word(static_cast<uint16_t>(storage.BitsStored - 1)));
    SetValue(dataSet, 0x0028, 0x0103, gdcm::VR::US, Word(storage.PixelRepresentation));
    SetValue(dataSet, 0x0028, 0x1052, gdcm::VR::DS, storage.Intercept);
    SetValue(dataSet, 0x0028, 0x1053, gdcm::VR::DS, storage.Slope);
    SetValue(dataSet, 0x0028, 0x0004, gdcm::VR::CS, storage.Photometric);
    gdcm::Writer writer;
    writer.SetFile(reader.GetFile());
    copies.push_back((directory / fs::path(files[slice]).filename()).string());
    writer.SetFileName(copies.back().c_str());
    EXPECT_TRUE(writer.Write()) << copies.back();
  }
  return copies;
}

std::vector<std::string>
GoodSeries()
{
  const fs::path series = TestData() / "dicom_good";
  EXPECT_TRUE(fs::is_directory(series)) << "run the pbdrr.MakeTestVolumes fixture first";
  return SliceFiles(series);
}
} // namespace

TEST(PbdrrDicomSliceReader, TestSeriesAsHUAndAsFloat)
{
  const auto good = GoodSeries();
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(good, true, "dicom_good as int16");
  ExpectSameAsSeriesReader<pbdrr::VolumeType>(good, true, "dicom_good as float");
}

// A gantry tilt: ImageSeriesReader's third direction (the step from the first slice to the last when not forced
// orthogonal) and spacing, reproduced; the slices' values made distinct, so that one out of place shows.
TEST(PbdrrDicomSliceReader, TiltedSeriesWithAndWithoutOrthogonalDirection)
{
  const fs::path tilt = TestData() / "dicom_tilt";
  ASSERT_TRUE(fs::is_directory(tilt)) << "run the pbdrr.MakeTestVolumes fixture first";
  const fs::path root = fs::temp_directory_path() / "pbdrr_slice_reader_tilt";
  Storage        distinct;
  distinct.Word = [](int16_t v, size_t, size_t) { return static_cast<uint16_t>(v); };
  const auto files = WriteStoredAs(SliceFiles(tilt), root, distinct);
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(files, false, "dicom_tilt, sheared");
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(files, true, "dicom_tilt, orthogonal");
  fs::remove_all(root);
}

// Every way of storing 16-bit values the reader decodes itself, each slice distinct: a slice put in another's place,
// or a value decoded or rescaled otherwise than GDCM does, shows.
TEST(PbdrrDicomSliceReader, SlicesStoredEveryWayItDecodes)
{
  const auto     good = GoodSeries();
  const fs::path root = fs::temp_directory_path() / "pbdrr_slice_reader";

  Storage distinct;
  distinct.Word = [](int16_t v, size_t, size_t) { return static_cast<uint16_t>(v); };
  const auto plain = WriteStoredAs(good, root / "int16", distinct);
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(plain, true, "int16 slices");
  ExpectSameAsSeriesReader<pbdrr::VolumeType>(plain, true, "int16 slices as float");

  // As the chest's scanner stores them: unsigned 12 of 16 bits, intercept -1024 (GDCM rescales them into int16).
  Storage unsigned12;
  unsigned12.BitsStored = 12;
  unsigned12.PixelRepresentation = 0;
  unsigned12.Intercept = "-1024";
  unsigned12.Word = [](int16_t v, size_t slice, size_t pixel) {
    return static_cast<uint16_t>(((v + 1024) & 0x0fff) | Junk(slice, pixel, 12));
  };
  const auto stored12 = WriteStoredAs(good, root / "unsigned12", unsigned12);
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(stored12, true, "unsigned 12-bit slices");
  ExpectSameAsSeriesReader<pbdrr::VolumeType>(stored12, true, "unsigned 12-bit slices as float");

  // Signed 12 of 16 bits: negative values are sign-extended from bit 11 over the junk.
  Storage signed12;
  signed12.BitsStored = 12;
  signed12.Word = [](int16_t v, size_t slice, size_t pixel) {
    return static_cast<uint16_t>((static_cast<uint16_t>(v) & 0x0fff) | Junk(slice, pixel, 12));
  };
  const auto signedStored = WriteStoredAs(good, root / "signed12", signed12);
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(signedStored, true, "signed 12-bit slices");

  // A fractional slope and intercept: GDCM rescales into double, read as float or (cast) as int16.
  Storage fractional;
  fractional.PixelRepresentation = 0;
  fractional.Slope = "0.5";
  fractional.Intercept = "-512.25";
  fractional.Word = [](int16_t v, size_t, size_t) { return static_cast<uint16_t>(v + 1024); };
  const auto rescaled = WriteStoredAs(good, root / "fractional", fractional);
  ExpectSameAsSeriesReader<pbdrr::VolumeType>(rescaled, true, "slices with a fractional slope");
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(rescaled, true, "slices with a fractional slope as int16");

  // 8 bits, decoded by GDCM itself (the reader decodes 16 bits itself), rescaled into int16.
  Storage unsigned8;
  unsigned8.BitsAllocated = 8;
  unsigned8.BitsStored = 8;
  unsigned8.PixelRepresentation = 0;
  unsigned8.Slope = "8";
  unsigned8.Intercept = "-1024";
  unsigned8.Word = [](int16_t v, size_t, size_t) { return static_cast<uint16_t>(std::clamp((v + 1024) / 8, 0, 255)); };
  const auto bytes = WriteStoredAs(good, root / "unsigned8", unsigned8);
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(bytes, true, "8-bit slices");
  fs::remove_all(root);
}

// What it does not read, it leaves to ImageSeriesReader: multi-frame files, and MONOCHROME1 slices (which
// GDCMImageIO inverts, with a warning of its own).
TEST(PbdrrDicomSliceReader, OtherFilesAreLeftToImageSeriesReader)
{
  const fs::path multiFrame = TestData() / "dicom_multiframe" / "MF0001.dcm";
  ASSERT_TRUE(fs::exists(multiFrame)) << "run the pbdrr.MakeTestVolumes fixture first";
  const std::vector<std::string> files{ multiFrame.string(), multiFrame.string() };
  EXPECT_EQ(pbdrr::ReadDicomSlices<pbdrr::HUVolumeType>(files, true), nullptr);

  const fs::path root = fs::temp_directory_path() / "pbdrr_slice_reader_left";
  Storage        inverted;
  inverted.Photometric = "MONOCHROME1";
  inverted.Word = [](int16_t v, size_t, size_t) { return static_cast<uint16_t>(v); };
  EXPECT_EQ(pbdrr::ReadDicomSlices<pbdrr::HUVolumeType>(WriteStoredAs(GoodSeries(), root, inverted), true), nullptr);
  fs::remove_all(root);
}

TEST(PbdrrDicomSliceReader, RealSeries)
{
  const fs::path chest = SharedData() / "ct/lidc-idri-0314-chest";
  const fs::path j2k = SharedData() / "ct/totalsegmentator/example_ct_dicom_jpeg2000";
  const fs::path tilted = SharedData() / "ct/philips-s21610-head-phantom/S3010";
  if (!fs::is_directory(chest) || !fs::is_directory(j2k) || !fs::is_directory(tilted))
  {
    GTEST_SKIP() << "SKIPPED: the real series of " << SharedData() << " are absent";
  }
  // The chest: unsigned 12-bit slices, intercept -1000, read as pbdrr reads them (int16).
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(SeriesFiles(chest), true, "the LIDC chest");
  // JPEG 2000 slices, decoded by GDCM (OpenJPEG) on several threads.
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(SeriesFiles(j2k), true, "the JPEG 2000 series");
  ExpectSameAsSeriesReader<pbdrr::VolumeType>(SeriesFiles(j2k), true, "the JPEG 2000 series as float");
  // A head phantom scanned with the gantry tilted.
  ExpectSameAsSeriesReader<pbdrr::HUVolumeType>(SeriesFiles(tilted), false, "the tilted head phantom");
}
