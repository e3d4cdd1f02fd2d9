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
// The DICOM header walker (pbdrr::FindDicomTruncation, pbdrr::IsDicomPart10File) on element streams built byte by byte:
// whole files walk clean, a file cut short is found with the place it ends, and what the walker does not know is left
// to GDCM (an empty answer).
#include "pbdrrDicomFileCheck.h"

#include "gtest/gtest.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace
{
namespace fs = std::filesystem;

const std::string explicitLittle = "1.2.840.10008.1.2.1";
const std::string implicitLittle = "1.2.840.10008.1.2";
const std::string explicitBig = "1.2.840.10008.1.2.2";

std::string
U16(uint16_t v)
{
  return { static_cast<char>(v & 0xFF), static_cast<char>(v >> 8) };
}

std::string
U32(uint32_t v)
{
  return U16(static_cast<uint16_t>(v & 0xFFFF)) + U16(static_cast<uint16_t>(v >> 16));
}

constexpr uint32_t undefinedLength = 0xFFFFFFFFu;

/** An explicit VR little endian element; `length` is the value's own unless given (a header that lies). */
std::string
Explicit(uint16_t group, uint16_t element, const std::string & vr, const std::string & value, int64_t length = -1)
{
  const uint32_t    declared = length < 0 ? static_cast<uint32_t>(value.size()) : static_cast<uint32_t>(length);
  const bool        longForm = vr == "OB" || vr == "OW" || vr == "SQ" || vr == "UN" || vr == "UT";
  const std::string header = U16(group) + U16(element) + vr;
  return (longForm ? header + std::string(2, '\0') + U32(declared) : header + U16(static_cast<uint16_t>(declared))) +
         value;
}

/** An implicit VR little endian element (also the form of items and delimiters). */
std::string
Implicit(uint16_t group, uint16_t element, const std::string & value, uint32_t length)
{
  return U16(group) + U16(element) + U32(length) + value;
}

std::string
Implicit(uint16_t group, uint16_t element, const std::string & value)
{
  return Implicit(group, element, value, static_cast<uint32_t>(value.size()));
}

std::string
Item(const std::string & content, uint32_t length)
{
  return Implicit(0xFFFE, 0xE000, content, length);
}

const std::string itemDelimiter = Implicit(0xFFFE, 0xE00D, "");
const std::string sequenceDelimiter = Implicit(0xFFFE, 0xE0DD, "");

/** A DICOM Part 10 file: preamble, "DICM", the meta group (explicit VR little endian) naming `syntax`, `dataSet`. */
std::string
Part10(const std::string & syntax, const std::string & dataSet)
{
  std::string uid = syntax;
  if (uid.size() % 2)
  {
    uid += '\0';
  }
  return std::string(128, '\0') + "DICM" + Explicit(0x0002, 0x0001, "OB", std::string("\0\1", 2)) +
         Explicit(0x0002, 0x0010, "UI", uid) + dataSet;
}

/** A small explicit VR data set: a few short elements, then 32 bytes of pixel data (OW) at the end. */
std::string
SmallDataSet()
{
  return Explicit(0x0008, 0x0060, "CS", "CT") + Explicit(0x0028, 0x0010, "US", U16(4)) +
         Explicit(0x0028, 0x0011, "US", U16(4)) + Explicit(0x7FE0, 0x0010, "OW", std::string(32, '\x7f'));
}

/** Writes `bytes` to a file of its own for the test and removes it afterwards. */
class TemporaryFile
{
public:
  explicit TemporaryFile(const std::string & bytes)
    : m_Path(fs::temp_directory_path() /
             ("pbdrr_dicom_file_check_" + std::to_string(getpid()) + "_" + std::to_string(s_Count++) + ".dcm"))
  {
    std::ofstream(m_Path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  ~TemporaryFile() { fs::remove(m_Path); }
  TemporaryFile(const TemporaryFile &) = delete;
  TemporaryFile &
  operator=(const TemporaryFile &) = delete;

  std::string
  Path() const
  {
    return m_Path.string();
  }

private:
  static inline unsigned s_Count = 0;
  fs::path               m_Path;
};

std::string
Truncation(const std::string & bytes)
{
  return pbdrr::FindDicomTruncation(TemporaryFile(bytes).Path());
}
} // namespace

TEST(PbdrrDicomFileCheck, WholeExplicitLittleEndianFileWalksClean)
{
  EXPECT_EQ(Truncation(Part10(explicitLittle, SmallDataSet())), "");
}

TEST(PbdrrDicomFileCheck, ValueCutShortIsFoundWithWhereTheFileEnds)
{
  const std::string whole = Part10(explicitLittle, SmallDataSet());
  const std::string cut = whole.substr(0, whole.size() - 1);
  // The pixel data value starts 32 bytes before the end of the whole file, after its 12-byte header.
  EXPECT_EQ(Truncation(cut),
            "element (7fe0,0010) needs 32 bytes at offset " + std::to_string(whole.size() - 32) +
              ", the file ends at " + std::to_string(cut.size()));
}

TEST(PbdrrDicomFileCheck, HeaderCutShortIsFound)
{
  const std::string whole = Part10(explicitLittle, SmallDataSet());
  const size_t      pixelData = whole.size() - 32 - 12;
  // Cut inside the tag and VR: the 8 bytes every header has are missing.
  EXPECT_EQ(Truncation(whole.substr(0, pixelData + 5)),
            "an element header needs 8 bytes at offset " + std::to_string(pixelData) + ", the file ends at " +
              std::to_string(pixelData + 5));
  // Cut inside the 32-bit length of a long-form (OW) header.
  EXPECT_EQ(Truncation(whole.substr(0, pixelData + 10)),
            "the length of element (7fe0,0010) needs 4 bytes at offset " + std::to_string(pixelData + 8) +
              ", the file ends at " + std::to_string(pixelData + 10));
}

TEST(PbdrrDicomFileCheck, OddLengthIsSkippedByteExact)
{
  // DICOM wants even lengths; the walker is not the judge of that (GDCM is): it skips exactly what a header says, and
  // finds the cut in the pixel data after the odd element where it is.
  const std::string whole = Part10(
    explicitLittle, Explicit(0x0008, 0x0070, "LO", "ACME") + Explicit(0x0008, 0x0060, "CS", "CTX") + SmallDataSet());
  EXPECT_EQ(Truncation(whole), "");
  EXPECT_EQ(Truncation(whole.substr(0, whole.size() - 1)),
            "element (7fe0,0010) needs 32 bytes at offset " + std::to_string(whole.size() - 32) +
              ", the file ends at " + std::to_string(whole.size() - 1));
  // An odd length one byte longer than the file.
  const std::string file = Part10(explicitLittle, Explicit(0x0008, 0x0060, "CS", "CT", 3));
  EXPECT_EQ(Truncation(file),
            "element (0008,0060) needs 3 bytes at offset " + std::to_string(file.size() - 2) + ", the file ends at " +
              std::to_string(file.size()));
}

TEST(PbdrrDicomFileCheck, SequenceOfUndefinedLengthIsWalkedItemByItem)
{
  // A referenced-series sequence: an undefined-length item (walked element by element), a defined-length one.
  const std::string inner = Explicit(0x0020, 0x000E, "UI", std::string("1.2.3.4\0", 8));
  const std::string sequence = Explicit(0x0008, 0x1115, "SQ", "", undefinedLength) +
                               Item(inner + itemDelimiter, undefinedLength) + Item(inner, inner.size()) +
                               sequenceDelimiter;
  const std::string after = Explicit(0x0028, 0x0010, "US", U16(4));
  EXPECT_EQ(Truncation(Part10(explicitLittle, sequence + after)), "");

  // Cut inside the value of the element in the first item: found there, not at the sequence.
  const std::string whole = Part10(explicitLittle, sequence + after);
  const size_t      innerValue = 128 + 4 + 14 + 28 + 12 + 8 + 8; // preamble, DICM, meta group, SQ, item, header
  EXPECT_EQ(Truncation(whole.substr(0, innerValue + 3)),
            "element (0020,000e) needs 8 bytes at offset " + std::to_string(innerValue) + ", the file ends at " +
              std::to_string(innerValue + 3));
  // Cut inside the defined-length second item.
  const size_t secondItem = innerValue + 8 + 8;
  EXPECT_EQ(Truncation(whole.substr(0, secondItem + 8 + 2)),
            "an item of (0008,1115) needs 16 bytes at offset " + std::to_string(secondItem + 8) +
              ", the file ends at " + std::to_string(secondItem + 10));
  // Cut before the sequence delimiter.
  const size_t delimiter = secondItem + 8 + 16;
  EXPECT_EQ(Truncation(whole.substr(0, delimiter)),
            "an item of (0008,1115) needs 8 bytes at offset " + std::to_string(delimiter) + ", the file ends at " +
              std::to_string(delimiter));
}

TEST(PbdrrDicomFileCheck, EncapsulatedPixelDataIsWalkedFragmentByFragment)
{
  const std::string pixelData = Explicit(0x7FE0, 0x0010, "OB", "", undefinedLength) + Item("", 0) +
                                Item(std::string(20, 'J'), 20) + Item(std::string(10, 'K'), 10) + sequenceDelimiter;
  const std::string whole = Part10(explicitLittle, Explicit(0x0028, 0x0010, "US", U16(4)) + pixelData);
  EXPECT_EQ(Truncation(whole), "");
  // Cut inside the second fragment.
  const size_t secondFragment = whole.size() - 8 - 10;
  EXPECT_EQ(Truncation(whole.substr(0, secondFragment + 4)),
            "a pixel-data fragment of (7fe0,0010) needs 10 bytes at offset " + std::to_string(secondFragment) +
              ", the file ends at " + std::to_string(secondFragment + 4));
}

TEST(PbdrrDicomFileCheck, ImplicitVRDataSetIsWalkedWithThirtyTwoBitLengths)
{
  const std::string dataSet = Implicit(0x0008, 0x0060, "CT") + Implicit(0x7FE0, 0x0010, std::string(32, '\x01'));
  const std::string whole = Part10(implicitLittle, dataSet);
  EXPECT_EQ(Truncation(whole), "");
  EXPECT_EQ(Truncation(whole.substr(0, whole.size() - 1)),
            "element (7fe0,0010) needs 32 bytes at offset " + std::to_string(whole.size() - 32) +
              ", the file ends at " + std::to_string(whole.size() - 1));
}

TEST(PbdrrDicomFileCheck, MetaGroupCutShortOrWithoutTransferSyntaxIsFound)
{
  const std::string meta = Part10(explicitLittle, "");
  // Nothing after the meta group: GDCM asserts on such a file.
  EXPECT_EQ(Truncation(meta),
            "the file meta information needs 8 bytes at offset " + std::to_string(meta.size()) + ", the file ends at " +
              std::to_string(meta.size()));
  // Cut right after "DICM": not even a tag.
  EXPECT_EQ(Truncation(meta.substr(0, 134)),
            "the file meta information needs 8 bytes at offset 132, the file ends at 134");
  const std::string noSyntax =
    std::string(128, '\0') + "DICM" + Explicit(0x0002, 0x0001, "OB", std::string("\0\1", 2)) + SmallDataSet();
  EXPECT_EQ(Truncation(noSyntax), "the file meta information has no transfer syntax (0002,0010)");
}

TEST(PbdrrDicomFileCheck, WhatTheWalkerDoesNotKnowIsLeftToGDCM)
{
  const std::string whole = Part10(explicitLittle, SmallDataSet());
  // Not DICOM Part 10: no "DICM" after the preamble, or shorter than the preamble.
  std::string notDicom = whole;
  notDicom[129] = 'X';
  EXPECT_EQ(Truncation(notDicom.substr(0, notDicom.size() - 1)), "");
  EXPECT_EQ(Truncation(whole.substr(0, 100)), "");
  // Big endian: the walker reads little endian only, even from a file cut short.
  const std::string big = Part10(explicitBig, SmallDataSet());
  EXPECT_EQ(Truncation(big.substr(0, big.size() - 1)), "");
  // A value representation it does not know ("XX"), before a value cut short.
  const std::string unknown =
    Part10(explicitLittle, Explicit(0x0009, 0x0010, "XX", "ab") + Explicit(0x7FE0, 0x0010, "OW", "", 64));
  EXPECT_EQ(Truncation(unknown), "");
}

TEST(PbdrrDicomFileCheck, Part10FileIsRecognisedByPreambleAndMark)
{
  const std::string whole = Part10(explicitLittle, SmallDataSet());
  EXPECT_TRUE(pbdrr::IsDicomPart10File(TemporaryFile(whole).Path()));
  EXPECT_TRUE(pbdrr::IsDicomPart10File(TemporaryFile(whole.substr(0, 132)).Path())) << "the mark alone is enough";
  EXPECT_FALSE(pbdrr::IsDicomPart10File(TemporaryFile(whole.substr(0, 131)).Path())) << "the mark cut short";
  std::string moved = whole;
  moved.replace(128, 4, "XXXX");
  EXPECT_FALSE(pbdrr::IsDicomPart10File(TemporaryFile(moved).Path()));
  EXPECT_FALSE(pbdrr::IsDicomPart10File(TemporaryFile("DICM" + moved.substr(4)).Path())) << "the mark at the start";
  EXPECT_FALSE(pbdrr::IsDicomPart10File((fs::temp_directory_path() / "pbdrr_no_such_file.dcm").string()));
}
