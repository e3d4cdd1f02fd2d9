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
// DRRImageFileIntegrity: every cut of a file of every format it knows is found, or leaves a file ITK reads to the
// same voxels (bytes no reader needs); a whole file, one with bytes appended, and a format it does not know pass.
#include "itkDRRImageFileIntegrity.h"

#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageRegionIterator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <unistd.h>

namespace
{
using VolumeType = itk::Image<short, 3>;

std::string
TemporaryFile(const std::string & name)
{
  // One directory per process: ctest runs the tests of this file in parallel.
  const std::filesystem::path directory =
    std::filesystem::temp_directory_path() / ("DRRImageFileIntegrityGTest-" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  return (directory / name).string();
}

/** 19 x 17 x 6 voxels of random HU: a compressed stream of several blocks, no two slices alike. */
VolumeType::Pointer
MakeVolume()
{
  auto                 volume = VolumeType::New();
  VolumeType::SizeType size{ { 19, 17, 6 } };
  volume->SetRegions(size);
  volume->Allocate();
  std::mt19937                         random(20261128);
  std::uniform_int_distribution<short> hu(-1000, 2000);
  for (itk::ImageRegionIterator<VolumeType> it(volume, volume->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    it.Set(hu(random));
  }
  return volume;
}

std::string
ReadBytes(const std::string & path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void
WriteBytes(const std::string & path, const std::string & bytes)
{
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

/** True if ITK reads `path` to exactly the voxels of `volume`; false if it reads others or throws. ITK's readers'
 * own messages (libtiff's, MetaIO's) are silenced: what they say is not what is tested. */
bool
ReadsTheSameVoxels(const std::string & path, const VolumeType * volume)
{
  std::streambuf * standardError = std::cerr.rdbuf(nullptr);
  bool             same = false;
  try
  {
    const auto read = itk::ReadImage<VolumeType>(path);
    same = read->GetLargestPossibleRegion() == volume->GetLargestPossibleRegion() &&
           std::equal(volume->GetBufferPointer(),
                      volume->GetBufferPointer() + volume->GetPixelContainer()->Size(),
                      read->GetBufferPointer());
  }
  catch (const itk::ExceptionObject &)
  {
    same = false;
  }
  std::cerr.rdbuf(standardError);
  return same;
}

/** A format as ITK writes it. Each has its own base name: NIfTI's reader, given volume.nii.gz, opens volume.nii if
 * there is one. */
struct WrittenFormat
{
  std::string Name;     // the file ITK writes (its extension picks the writer)
  bool        Compress; // ITK's UseCompression
  std::string Data;     // the pixels' own file, for a header apart ("" if none)
};

/** Test names and failures show the format's file name, not its bytes. */
void
PrintTo(const WrittenFormat & format, std::ostream * os)
{
  *os << format.Name;
}

class DRRImageFileIntegrityFormats : public ::testing::TestWithParam<WrittenFormat>
{};

/** The lengths a sweep cuts a file of `size` bytes to: every one in the first 700 (headers), then every 23rd, and the
 * last byte missing. */
std::vector<size_t>
CutLengths(size_t size)
{
  std::vector<size_t> lengths;
  for (size_t n = 0; n < size; n += n < 700 ? 1 : 23)
  {
    lengths.push_back(n);
  }
  lengths.push_back(size - 1);
  return lengths;
}
} // namespace

TEST_P(DRRImageFileIntegrityFormats, EveryCutIsFoundOrLeavesTheSameVoxels)
{
  const WrittenFormat format = GetParam();
  const auto          volume = MakeVolume();
  const std::string   path = TemporaryFile(format.Name);
  itk::WriteImage(volume, path, format.Compress);
  ASSERT_TRUE(itk::DRRImageFileIntegrity::IsCheckedFormat(path));
  ASSERT_EQ(itk::DRRImageFileIntegrity::FindDamage(path), "") << "the whole file";
  ASSERT_TRUE(ReadsTheSameVoxels(path, volume));

  // The file that holds the pixels is cut: the file itself, or the data file beside its header.
  const std::string cutPath = format.Data.empty() ? path : TemporaryFile(format.Data);
  const std::string whole = ReadBytes(cutPath);
  unsigned          found = 0, harmless = 0;
  for (const size_t length : CutLengths(whole.size()))
  {
    WriteBytes(cutPath, whole.substr(0, length));
    const std::string damage = itk::DRRImageFileIntegrity::FindDamage(path);
    if (damage.empty())
    {
      // Not found: then the cut took bytes no reader needs, and ITK reads the same voxels.
      EXPECT_TRUE(ReadsTheSameVoxels(path, volume)) << format.Name << " cut to " << length << " of " << whole.size()
                                                    << " bytes: not found, and read to other voxels";
      ++harmless;
    }
    else
    {
      ++found;
      EXPECT_NE(damage.find("truncated"), std::string::npos)
        << format.Name << " cut to " << length << ": the message says what happened: " << damage;
    }
  }
  EXPECT_GT(found, 0u);
  // Bytes appended are not damage.
  WriteBytes(cutPath, whole + std::string(100, '\0'));
  EXPECT_EQ(itk::DRRImageFileIntegrity::FindDamage(path), "") << "bytes appended";
  WriteBytes(cutPath, whole);
  // Check() throws what FindDamage() finds, naming the file.
  EXPECT_NO_THROW(itk::DRRImageFileIntegrity::Check(path));
  WriteBytes(cutPath, whole.substr(0, whole.size() / 2));
  try
  {
    itk::DRRImageFileIntegrity::Check(path);
    ADD_FAILURE() << "Check() did not throw on a file cut in half";
  }
  catch (const itk::ExceptionObject & error)
  {
    EXPECT_NE(std::string(error.GetDescription()).find(format.Name), std::string::npos) << error.GetDescription();
  }
}

INSTANTIATE_TEST_SUITE_P(AllFormats,
                         DRRImageFileIntegrityFormats,
                         ::testing::Values(WrittenFormat{ "volume.mha", false, "" },
                                           WrittenFormat{ "zlib.mha", true, "" },
                                           WrittenFormat{ "apart.mhd", false, "apart.raw" },
                                           WrittenFormat{ "volume.nrrd", false, "" },
                                           WrittenFormat{ "gzip.nrrd", true, "" },
                                           WrittenFormat{ "apart.nhdr", false, "apart.raw" },
                                           WrittenFormat{ "volume.nii", false, "" },
                                           WrittenFormat{ "gzip.nii.gz", true, "" },
                                           WrittenFormat{ "pair.hdr", false, "pair.img" },
                                           WrittenFormat{ "volume.tif", false, "" }),
                         [](const ::testing::TestParamInfo<WrittenFormat> & info) {
                           std::string name = info.param.Name;
                           std::replace(name.begin(), name.end(), '.', '_');
                           return name;
                         });

TEST(DRRImageFileIntegrity, AHeaderThatPromisesMoreThanItsDataIsFound)
{
  const auto        volume = MakeVolume();
  const std::string meta = TemporaryFile("promise.mha");
  itk::WriteImage(volume, meta);
  std::string  bytes = ReadBytes(meta);
  const size_t at = bytes.find("DimSize = 19 17 6");
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, 17, "DimSize = 19 17 7");
  WriteBytes(meta, bytes);
  EXPECT_NE(itk::DRRImageFileIntegrity::FindDamage(meta).find("promises 4522"), std::string::npos)
    << itk::DRRImageFileIntegrity::FindDamage(meta); // 19 x 17 x 7 x 2 bytes

  // NIfTI-1: dim[3] (a short at byte 46) one more.
  const std::string nifti = TemporaryFile("promise.nii");
  itk::WriteImage(volume, nifti);
  bytes = ReadBytes(nifti);
  short slices = 0;
  std::memcpy(&slices, &bytes[46], 2);
  ASSERT_EQ(slices, 6);
  slices = 7;
  std::memcpy(&bytes[46], &slices, 2);
  WriteBytes(nifti, bytes);
  EXPECT_NE(itk::DRRImageFileIntegrity::FindDamage(nifti).find("promises 4522"), std::string::npos)
    << itk::DRRImageFileIntegrity::FindDamage(nifti);
}

// Header values that are not numbers an int64 holds are not sized (the reader words them), never an exception of
// another kind; a negative HeaderSize (the data are the data file's last bytes) is read as negative.
TEST(DRRImageFileIntegrity, HeaderNumbersOutOfRangeAreNotThrown)
{
  const auto        volume = MakeVolume();
  const std::string header = TemporaryFile("numbers.mhd");
  itk::WriteImage(volume, header);
  const std::string original = ReadBytes(header);
  const auto        withLine = [&](const std::string & line) {
    std::string bytes = original;
    bytes.insert(bytes.find("ElementDataFile"), line + "\n");
    WriteBytes(header, bytes);
  };
  withLine("ElementNumberOfChannels = 99999999999999999999999");
  EXPECT_NO_THROW(EXPECT_EQ(itk::DRRImageFileIntegrity::FindDamage(header), ""));
  withLine("HeaderSize = 99999999999999999999999");
  EXPECT_NO_THROW(itk::DRRImageFileIntegrity::FindDamage(header));
  // HeaderSize -1 with the data file cut by one byte: found (it read as 0 before, and ought to be found either way).
  withLine("HeaderSize = -1");
  const std::string data = TemporaryFile("numbers.raw");
  const std::string pixels = ReadBytes(data);
  EXPECT_EQ(itk::DRRImageFileIntegrity::FindDamage(header), "");
  WriteBytes(data, pixels.substr(1));
  EXPECT_NE(itk::DRRImageFileIntegrity::FindDamage(header).find("truncated"), std::string::npos);
  // ... and with a byte put before the data: whole, the data being the last bytes.
  WriteBytes(data, "x" + pixels);
  EXPECT_EQ(itk::DRRImageFileIntegrity::FindDamage(header), "");
}

TEST(DRRImageFileIntegrity, ACorruptCompressedStreamIsFound)
{
  const auto volume = MakeVolume();
  for (const std::string name : { "corrupt.nii.gz", "corrupt.mha", "corrupt.nrrd" })
  {
    const std::string path = TemporaryFile(name);
    itk::WriteImage(volume, path, true);
    std::string bytes = ReadBytes(path);
    bytes[bytes.size() - 200] ^= 0x5a; // inside the deflated pixels: the stream's check (CRC-32, Adler-32) fails
    WriteBytes(path, bytes);
    const std::string damage = itk::DRRImageFileIntegrity::FindDamage(path);
    EXPECT_NE(damage.find("damaged"), std::string::npos) << name << ": " << damage;
  }
}

TEST(DRRImageFileIntegrity, MissingFilesAndOtherFormats)
{
  EXPECT_NE(itk::DRRImageFileIntegrity::FindDamage(TemporaryFile("absent.mha")).find("cannot open it"),
            std::string::npos);
  // A header whose data file is missing.
  const std::string header = TemporaryFile("orphan.mhd");
  itk::WriteImage(MakeVolume(), header);
  std::filesystem::remove(TemporaryFile("orphan.raw"));
  EXPECT_NE(itk::DRRImageFileIntegrity::FindDamage(header).find("cannot open its data file"), std::string::npos);
  // Formats it does not know are not checked.
  EXPECT_FALSE(itk::DRRImageFileIntegrity::IsCheckedFormat("slice.png"));
  EXPECT_EQ(itk::DRRImageFileIntegrity::FindDamage(TemporaryFile("absent.png")), "");
}

TEST(DRRImageFileIntegrity, ATiffStripPastTheEndIsFound)
{
  // ITK's writer puts a TIFF's directories after its pixels, so that any cut takes a directory first; other writers
  // put them first (libtiff's default), and a cut then takes only pixels. One page of 8-bit pixels, made so.
  const uint16_t width = 40, height = 30;
  const uint32_t dataStart = 8 + 2 + 8 * 12 + 4;
  std::string    tiff("II*\0", 4);
  const auto     put = [&tiff](uint64_t value, unsigned bytes) {
    for (unsigned k = 0; k < bytes; ++k)
    {
      tiff.push_back(static_cast<char>((value >> (8 * k)) & 0xff));
    }
  };
  put(8, 4);
  put(8, 2); // entries
  const uint32_t entries[8][3] = { { 256, 3, width },  { 257, 3, height },
                                   { 258, 3, 8 },      { 259, 3, 1 },
                                   { 262, 3, 1 },      { 273, 4, dataStart },
                                   { 278, 3, height }, { 279, 4, width * height } };
  for (const auto & entry : entries)
  {
    put(entry[0], 2);
    put(entry[1], 2);
    put(1, 4);
    put(entry[2], 4);
  }
  put(0, 4); // no next directory
  ASSERT_EQ(tiff.size(), dataStart);
  tiff += std::string(width * height, '\x7f');
  const std::string path = TemporaryFile("directory_first.tif");
  WriteBytes(path, tiff);
  EXPECT_EQ(itk::DRRImageFileIntegrity::FindDamage(path), "");
  WriteBytes(path, tiff.substr(0, tiff.size() - 1));
  EXPECT_NE(itk::DRRImageFileIntegrity::FindDamage(path).find("strip 0 (bytes 110 to 1310) is past the end"),
            std::string::npos)
    << itk::DRRImageFileIntegrity::FindDamage(path);
}
