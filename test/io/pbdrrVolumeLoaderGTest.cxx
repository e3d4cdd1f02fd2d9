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
// pbdrr's volume loader on damaged and compressed DICOM: every truncation of a slice is refused (none reaches GDCM,
// which aborts on some), and JPEG 2000 slices decode to the pixel range their own headers declare.
#include "pbdrrDicomFileCheck.h"
#include "pbdrrVolumeLoader.h"

#include "gdcmScanner.h"
#include "itkImageFileReader.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
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

std::vector<double>
Numbers(const char * text)
{
  std::vector<double> values;
  std::string         s = text ? text : "";
  std::replace(s.begin(), s.end(), '\\', ' ');
  std::istringstream stream(s);
  for (double v; stream >> v;)
  {
    values.push_back(v);
  }
  return values;
}
} // namespace

TEST(PbdrrDicomTruncation, EveryCutOfASliceIsRefusedAndNoneReachesGDCM)
{
  const fs::path series = TestData() / "dicom_good";
  const fs::path victim = series / "IM0005.dcm";
  ASSERT_TRUE(fs::exists(victim)) << "run the pbdrr.MakeTestVolumes fixture first";
  EXPECT_EQ(pbdrr::FindDicomTruncation(victim.string()), "") << "the whole slice is not damaged";
  const auto whole = pbdrr::LoadVolume(series.string(), "");
  ASSERT_EQ(whole.Grid()->GetLargestPossibleRegion().GetSize()[2], 8u);

  const fs::path copy = fs::temp_directory_path() / "pbdrr_truncation_sweep";
  const auto     size = fs::file_size(victim);
  // The pixel data element (implicit VR, as ITK writes it: an 8-byte header) ends the file with its 16 x 16 x 2 bytes.
  const uintmax_t pixelData = size - 16 * 16 * 2 - 8;
  for (uintmax_t length = 0; length < size; ++length)
  {
    fs::remove_all(copy);
    fs::copy(series, copy);
    fs::resize_file(copy / "IM0005.dcm", length);
    if (length > pixelData)
    {
      EXPECT_NE(pbdrr::FindDicomTruncation((copy / "IM0005.dcm").string()), "")
        << "a slice cut to " << length << " of " << size << " bytes, in its pixel data, passes the check";
    }
    // Cut anywhere, the series is refused with a message naming the slice (a crash in GDCM would end this program);
    // cut before its "DICM" mark it is no longer DICOM, and the message names it beside the gap it leaves.
    try
    {
      pbdrr::LoadVolume(copy.string(), "");
      ADD_FAILURE() << "a series with a slice cut to " << length << " of " << size << " bytes was read";
    }
    catch (const std::runtime_error & e)
    {
      const std::string message = e.what();
      EXPECT_NE(message.find("IM0005.dcm"), std::string::npos)
        << "cut to " << length << " bytes: the message does not name the slice: " << message;
    }
  }
  fs::remove_all(copy);
}

TEST(PbdrrDicomTruncation, EncapsulatedPixelDataCutShortIsFound)
{
  const fs::path j2k = fs::path(PBDRR_SHARED_DATA_DIR) / "ct/totalsegmentator/example_ct_dicom_jpeg2000";
  if (!fs::is_directory(j2k))
  {
    GTEST_SKIP() << "SKIPPED: " << j2k << " is absent (real data from ../shared/data)";
  }
  const fs::path slice = *fs::directory_iterator(j2k);
  EXPECT_EQ(pbdrr::FindDicomTruncation(slice.string()), "") << slice;
  const fs::path copy = fs::temp_directory_path() / "pbdrr_j2k_truncation.dcm";
  const auto     size = fs::file_size(slice);
  // Cuts in the header, at the fragments' start, inside the codestream, and one byte short of the end.
  for (const uintmax_t length : { uintmax_t{ 200 }, uintmax_t{ 3000 }, size / 2, size - 9, size - 1 })
  {
    fs::copy_file(slice, copy, fs::copy_options::overwrite_existing);
    fs::resize_file(copy, length);
    EXPECT_NE(pbdrr::FindDicomTruncation(copy.string()), "") << "cut to " << length << " of " << size << " bytes";
  }
  fs::remove(copy);
}

TEST(PbdrrVolumeLoader, Jpeg2000SlicesDecodeToTheRangeTheirHeadersDeclare)
{
  const fs::path j2k = fs::path(PBDRR_SHARED_DATA_DIR) / "ct/totalsegmentator/example_ct_dicom_jpeg2000";
  if (!fs::is_directory(j2k))
  {
    GTEST_SKIP() << "SKIPPED: " << j2k << " is absent (real data from ../shared/data)";
  }
  const auto                loaded = pbdrr::LoadVolume(j2k.string(), "");
  const itk::ImageBase<3> * image = loaded.Grid();
  const auto                size = image->GetLargestPossibleRegion().GetSize();
  // The slice's values, whichever type the loader chose (int16 when the headers say they fit).
  const auto sliceRange = [&](size_t k) {
    const size_t pixels = size[0] * size[1];
    return loaded.Visit([&](const auto * volume) {
      const auto * slice = volume->GetBufferPointer() + k * pixels;
      const auto   range = std::minmax_element(slice, slice + pixels);
      return std::make_pair(static_cast<double>(*range.first), static_cast<double>(*range.second));
    });
  };
  ASSERT_EQ(size[0], 512u);
  ASSERT_EQ(size[1], 512u);
  ASSERT_EQ(size[2], 20u);

  // The encoder wrote each slice's smallest and largest stored value into its header (0028,0106/0107): the decoded
  // slice at that slice's position must span exactly that range, rescaled to HU.
  std::vector<std::string> files;
  for (const auto & entry : fs::directory_iterator(j2k))
  {
    files.push_back(entry.path().string());
  }
  const gdcm::Tag position(0x0020, 0x0032), smallest(0x0028, 0x0106), largest(0x0028, 0x0107);
  const gdcm::Tag slope(0x0028, 0x1053), intercept(0x0028, 0x1052);
  gdcm::Scanner   scanner;
  for (const auto & tag : { position, smallest, largest, slope, intercept })
  {
    scanner.AddTag(tag);
  }
  ASSERT_TRUE(scanner.Scan(files));
  const auto value = [&](const std::string & file, const gdcm::Tag & tag) {
    return Numbers(scanner.GetValue(file.c_str(), tag)).at(0);
  };
  unsigned int checked = 0;
  for (const auto & file : files)
  {
    const auto   ipp = Numbers(scanner.GetValue(file.c_str(), position));
    const double a = value(file, slope);
    const double b = value(file, intercept);
    ASSERT_EQ(ipp.size(), 3u) << file;
    pbdrr::VolumeType::PointType point;
    for (unsigned int i = 0; i < 3; ++i)
    {
      point[i] = ipp[i];
    }
    const auto index = image->TransformPhysicalPointToContinuousIndex<double>(point);
    const long k = std::lround(index[2]);
    ASSERT_NEAR(index[2], static_cast<double>(k), 1e-3) << file << ": not on a slice of the volume";
    ASSERT_NEAR(index[0], 0.0, 1e-3) << file;
    ASSERT_NEAR(index[1], 0.0, 1e-3) << file;
    const auto range = sliceRange(static_cast<size_t>(k));
    EXPECT_EQ(range.first, a * value(file, smallest) + b) << file << " (slice " << k << ")";
    EXPECT_EQ(range.second, a * value(file, largest) + b) << file << " (slice " << k << ")";
    ++checked;
  }
  EXPECT_EQ(checked, 20u);
}

// A CT is held as its file stores it: int16 (2 bytes per voxel) where the file says every value fits an int16 (a DICOM
// series by its stored bits, slope and intercept; a volume file by its pixel type), float otherwise; the values are
// the same either way.
TEST(PbdrrVolumeLoader, AnInt16CtIsHeldAsInt16AndOtherVolumesAsFloat)
{
  const fs::path series = TestData() / "dicom_good";
  const fs::path phantom = TestData() / "phantom.mha";         // short HU
  const fs::path extremes = TestData() / "float_extremes.mha"; // float HU
  ASSERT_TRUE(fs::exists(series) && fs::exists(phantom) && fs::exists(extremes))
    << "run the pbdrr.MakeTestVolumes fixture first";
  const auto dicom = pbdrr::LoadVolume(series.string(), "");
  EXPECT_TRUE(dicom.HoldsHU()) << "the test series is 16-bit with slope 1";
  const auto file = pbdrr::LoadVolume(phantom.string(), "");
  ASSERT_TRUE(file.HoldsHU());
  // The int16 volume, in its own type and as float (a copy), holds the values ITK's reader reads as float.
  const auto   asFloat = itk::ReadImage<pbdrr::VolumeType>(phantom.string());
  const auto   copied = file.AsFloat();
  const size_t voxels = asFloat->GetBufferedRegion().GetNumberOfPixels();
  ASSERT_EQ(copied->GetBufferedRegion().GetNumberOfPixels(), voxels);
  EXPECT_TRUE(copied->GetOrigin() == asFloat->GetOrigin() && copied->GetSpacing() == asFloat->GetSpacing() &&
              copied->GetDirection() == asFloat->GetDirection());
  size_t different = 0;
  file.Visit([&](const auto * volume) {
    ASSERT_EQ(sizeof(*volume->GetBufferPointer()), 2u);
    for (size_t v = 0; v < voxels; ++v)
    {
      different += static_cast<float>(volume->GetBufferPointer()[v]) != asFloat->GetBufferPointer()[v] ? 1 : 0;
      different += copied->GetBufferPointer()[v] != asFloat->GetBufferPointer()[v] ? 1 : 0;
    }
  });
  EXPECT_EQ(different, 0u);
  const auto floating = pbdrr::LoadVolume(extremes.string(), "");
  EXPECT_FALSE(floating.HoldsHU());
  EXPECT_EQ(floating.Grid(), floating.AsFloat().GetPointer()) << "a float volume is handed over, not copied";
  // An empty one says so instead of handing over null.
  EXPECT_THROW(pbdrr::LoadedVolume().Grid(), std::logic_error);
}
