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
// Tests of DRRProjectionGeometryFileIO (reading and writing the geometry-file format) and DRRNumberParser. Expected
// values are written by hand; a round trip compares every field of the geometry bit for bit.

#include "gtest/gtest.h"

#include "PointBasedDRRTestHelpers.h"

#include "itkDRRNumberParser.h"
#include "itkDRRPolicies.h"
#include "itkDRRProjectionGeometryFileIO.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>

namespace
{
using PointBasedDRRTest::Contains;
using PointBasedDRRTest::ExceptionMessage;
using PointBasedDRRTest::Pt;
using PointBasedDRRTest::Vec;
using GeometryType = itk::DRRProjectionGeometry;
using IOType = itk::DRRProjectionGeometryFileIO;
using PointType = GeometryType::PointType;
using VectorType = GeometryType::VectorType;
using ProjectionEnum = GeometryType::ProjectionEnum;

GeometryType::DetectorVectorType
Vec2(double a, double b)
{
  GeometryType::DetectorVectorType v;
  v[0] = a;
  v[1] = b;
  return v;
}

/** The bits of a double as text: 0 and -0 differ, as do neighbouring doubles. */
std::string
Bits(double value)
{
  std::ostringstream os;
  os << std::hexfloat << value;
  return os.str();
}

template <typename TArray>
void
ExpectSameBits(const TArray & actual, const TArray & expected, unsigned int count, const std::string & what)
{
  for (unsigned int d = 0; d < count; ++d)
  {
    EXPECT_EQ(std::memcmp(&actual[d], &expected[d], sizeof(double)), 0)
      << what << "[" << d << "]: " << Bits(actual[d]) << " instead of " << Bits(expected[d]);
  }
}

/** Every field of two geometries, bit for bit. */
void
ExpectSameGeometry(const GeometryType * actual, const GeometryType * expected, const std::string & what)
{
  EXPECT_EQ(actual->GetProjection(), expected->GetProjection()) << what;
  const double actualScalars[3] = { actual->GetSourceToIsocenterDistance(),
                                    actual->GetSourceToDetectorDistance(),
                                    actual->GetGantryAngleInDegrees() };
  const double expectedScalars[3] = { expected->GetSourceToIsocenterDistance(),
                                      expected->GetSourceToDetectorDistance(),
                                      expected->GetGantryAngleInDegrees() };
  ExpectSameBits(actualScalars, expectedScalars, 3, what + ": sad, sid, gantry");
  ExpectSameBits(actual->GetNormal(), expected->GetNormal(), 3, what + ": nrm");
  ExpectSameBits(actual->GetViewUp(), expected->GetViewUp(), 3, what + ": vup");
  ExpectSameBits(actual->GetIsocenter(), expected->GetIsocenter(), 3, what + ": isocenter");
  EXPECT_EQ(actual->GetDetectorSize(), expected->GetDetectorSize()) << what;
  ExpectSameBits(actual->GetDetectorSpacing(), expected->GetDetectorSpacing(), 2, what + ": spacing");
  ExpectSameBits(actual->GetDetectorOffset(), expected->GetDetectorOffset(), 2, what + ": offset");
  EXPECT_EQ(actual->GetColumnsMirrored(), expected->GetColumnsMirrored()) << what << ": mirror";
}

/** A geometry that differs from every geometry below in every field, so that a key Write() leaves out shows. */
GeometryType::Pointer
MakeOtherGeometry()
{
  auto other = GeometryType::New();
  other->SetProjection(ProjectionEnum::Parallel);
  other->SetSourceToIsocenterDistance(3.25);
  other->SetSourceToDetectorDistance(4.75);
  other->SetGantryAngleInDegrees(-123.0);
  other->SetNormal(Vec(0.0, 0.0, -1.0));
  other->SetViewUp(Vec(0.0, 1.0, 0.0));
  other->SetIsocenter(Pt(-9.0, -9.0, -9.0));
  other->SetDetectorSize({ { 7, 9 } });
  other->SetDetectorSpacing(Vec2(0.125, 0.25));
  other->SetDetectorOffset(Vec2(-99.0, 99.0));
  other->SetColumnsMirrored(true);
  return other;
}

/** Writes geometry to text, reads the text into MakeOtherGeometry() and expects geometry bit for bit. */
std::string
ExpectRoundTrip(const GeometryType * geometry, const std::string & what)
{
  std::ostringstream written;
  EXPECT_NO_THROW(IOType::WriteToStream(written, geometry)) << what;
  auto               readBack = MakeOtherGeometry();
  std::istringstream text(written.str());
  EXPECT_NO_THROW(IOType::ReadFromStream(text, readBack, "written")) << what << ":\n" << written.str();
  ExpectSameGeometry(readBack, geometry, what + ", written as:\n" + written.str());
  return written.str();
}

} // namespace

// ---------------------------------------------------------------------------------------------------------------------
// Writing, then reading back: the same geometry bit for bit.

TEST(DRRProjectionGeometryFileIO, RoundTripPerspectiveGantryWithOffsets)
{
  auto geometry = GeometryType::New();
  geometry->SetGantryAngleInDegrees(37.3); // (cos, -sin) of it: no short decimal
  geometry->SetSourceToIsocenterDistance(1000.0 / 3.0);
  geometry->SetSourceToDetectorDistance(1536.1);
  geometry->SetViewUp(Vec(0.1, -0.2, 0.9));
  geometry->SetIsocenter(Pt(-12.345678901234567, 0.1 + 0.2, -0.0));
  geometry->SetDetectorSize({ { 321, 17 } });
  geometry->SetDetectorSpacing(Vec2(0.388, 1.0 / 7.0));
  geometry->SetDetectorOffset(Vec2(-3.5e-3, 2.0 / 3.0));
  const std::string text = ExpectRoundTrip(geometry, "perspective, gantry 37.3");
  // The normal is the gantry angle's: no nrm line.
  EXPECT_FALSE(Contains(text, "nrm")) << text;
  EXPECT_TRUE(Contains(text, "\nprojection perspective\n")) << text;
  EXPECT_TRUE(Contains(text, "\ngantry 37.3\n")) << text;
  EXPECT_TRUE(Contains(text, "\ncols 321\n")) << text;
}

TEST(DRRProjectionGeometryFileIO, RoundTripParallelNormalWithOffsets)
{
  auto geometry = GeometryType::New();
  geometry->SetProjection(ProjectionEnum::Parallel);
  geometry->SetGantryAngleInDegrees(12.0); // kept, though the normal below overrides it
  geometry->SetNormal(Vec(1.0, 2.0, -0.5));
  geometry->SetViewUp(Vec(0.0, 0.0, -1.0));
  geometry->SetSourceToIsocenterDistance(250.0);
  geometry->SetSourceToDetectorDistance(0.1);
  geometry->SetIsocenter(Pt(1e-300, -7.0e6, 3.0));
  geometry->SetDetectorSize({ { 1, 1000000 } });
  geometry->SetDetectorSpacing(Vec2(1e-6, 1e7));
  geometry->SetDetectorOffset(Vec2(-0.3, 1e-5));
  const std::string text = ExpectRoundTrip(geometry, "parallel, nrm (1, 2, -0.5)");
  EXPECT_TRUE(Contains(text, "\nprojection parallel\n")) << text;
  // gantry first, then nrm, which overrides the gantry's normal when read.
  ASSERT_TRUE(Contains(text, "\ngantry 12\n")) << text;
  ASSERT_TRUE(Contains(text, "\nnrm ")) << text;
  EXPECT_LT(text.find("\ngantry "), text.find("\nnrm ")) << text;
}

TEST(DRRProjectionGeometryFileIO, RoundTripDefaultAndExplicitGeometries)
{
  // The default normal is (1, 0, 0), gantry 0's is (1, -0, 0): a bit apart, so nrm is written.
  ExpectRoundTrip(GeometryType::New(), "default geometry");

  auto perspective = GeometryType::New();
  perspective->SetExplicitPerspectiveGeometry(
    Pt(600.0, 10.0, -20.0), Pt(-900.0, 40.0, 15.0), Vec(0.0, 0.6, 0.8), Vec(0.0, 0.8, -0.6));
  ExpectRoundTrip(perspective, "explicit perspective");

  auto parallel = GeometryType::New();
  parallel->SetExplicitParallelGeometry(Pt(5.0, -6.0, 7.0), Vec(0.0, 1.0, 0.0), Vec(0.0, 0.0, -1.0));
  ExpectRoundTrip(parallel, "explicit parallel");
}

TEST(DRRProjectionGeometryFileIO, RoundTripSubnormalAndExtremeNumbers)
{
  // The decimal form of a subnormal number reads with ERANGE, which the reader refuses: it is written in hexadecimal
  // (found by the geometry fuzzer: a parallel geometry's SAD of 0x1p-1074 verifies).
  auto geometry = GeometryType::New();
  geometry->SetSourceToIsocenterDistance(std::numeric_limits<double>::denorm_min());
  geometry->SetSourceToDetectorDistance(-std::numeric_limits<double>::denorm_min() * 12345.0);
  geometry->SetGantryAngleInDegrees(-1e300); // a finite angle in radians, so a finite normal
  geometry->SetIsocenter(Pt(std::numeric_limits<double>::min(), -std::numeric_limits<double>::lowest(), 1e-310));
  geometry->SetDetectorOffset(Vec2(std::numeric_limits<double>::min() / 2.0, -0.0));
  const std::string text = ExpectRoundTrip(geometry, "subnormal and extreme numbers");
  EXPECT_TRUE(Contains(text, "\nsad 0x0.0000000000001p-1022\n")) << text;
  EXPECT_TRUE(Contains(text, "\ngantry -1e+300\n")) << text;
  EXPECT_TRUE(Contains(text, " 1.7976931348623157e+308 ")) << text;
}

TEST(DRRProjectionGeometryFileIO, RoundTripRandomGeometries)
{
  // Full-mantissa values of every magnitude the reader accepts, normals of every direction (a third of the normals
  // v / |v| are moved by an ulp if normalized again), negative zeros.
  std::mt19937_64                         random(20261123);
  std::normal_distribution<double>        normal;
  std::uniform_int_distribution<int>      exponent(-12, 6);
  std::uniform_int_distribution<unsigned> count(1, 1000000);
  auto                                    value = [&]() {
    const double x = normal(random) * std::pow(10.0, exponent(random));
    return random() % 17 == 0 ? -0.0 : x;
  };
  for (unsigned int trial = 0; trial < 2000; ++trial)
  {
    auto         geometry = GeometryType::New();
    const auto & beams = itk::DRRPolicies::Beams::GetEntries();
    geometry->SetProjection(std::next(beams.begin(), trial % beams.size())->Id);
    geometry->SetColumnsMirrored(trial % 5 == 1);
    geometry->SetSourceToIsocenterDistance(value());
    geometry->SetSourceToDetectorDistance(value());
    geometry->SetGantryAngleInDegrees(360.0 * normal(random));
    if (trial % 3 != 0)
    {
      VectorType n = Vec(value(), value(), value());
      n[trial % 3] += 1e-3; // never zero
      geometry->SetNormal(n);
    }
    geometry->SetViewUp(Vec(value(), value(), value()));
    geometry->SetIsocenter(Pt(value(), value(), value()));
    geometry->SetDetectorSize({ { count(random), count(random) } });
    geometry->SetDetectorSpacing(Vec2(value(), value()));
    geometry->SetDetectorOffset(Vec2(value(), value()));
    ExpectRoundTrip(geometry, "random geometry " + std::to_string(trial));
    if (HasFailure())
    {
      break;
    }
  }
}

TEST(DRRProjectionGeometryFileIO, SetNormalKeepsTheNormalInForce)
{
  // What the round trip of nrm rests on: setting the normal in force again changes no bit.
  std::mt19937_64                  random(7);
  std::normal_distribution<double> normal;
  auto                             geometry = GeometryType::New();
  for (unsigned int trial = 0; trial < 100000; ++trial)
  {
    geometry->SetNormal(Vec(normal(random), normal(random), normal(random)) * std::pow(10.0, trial % 9 - 4.0));
    const VectorType inForce = geometry->GetNormal();
    geometry->SetNormal(inForce);
    ExpectSameBits(geometry->GetNormal(), inForce, 3, "normal " + std::to_string(trial));
    if (HasFailure())
    {
      break;
    }
  }
  // A vector that is not of unit length is still normalized: (0, 3, 4) / 5.
  geometry->SetNormal(Vec(0.0, 3.0, 4.0));
  EXPECT_EQ(geometry->GetNormal(), Vec(0.0, 0.6, 0.8));
}

TEST(DRRProjectionGeometryFileIO, WritesEveryKeyOnce)
{
  auto geometry = GeometryType::New();
  geometry->SetNormal(Vec(0.0, 1.0, 0.0));
  std::ostringstream written;
  IOType::WriteToStream(written, geometry);
  const std::string text = "\n" + written.str();
  for (const char * key :
       { "projection", "sad", "sid", "gantry", "nrm", "vup", "isocenter", "cols", "rows", "spacing", "offset" })
  {
    const std::string line = "\n" + std::string(key) + " ";
    const size_t      at = text.find(line);
    EXPECT_NE(at, std::string::npos) << key << " missing:" << text;
    EXPECT_EQ(text.find(line, at + 1), std::string::npos) << key << " twice:" << text;
  }
  // The defaults, by hand: SAD 1000, SID 1500, 256 x 256 pixels of 1 mm, vup (0, 0, 1).
  EXPECT_TRUE(Contains(text,
                       "\nsad 1000\nsid 1500\ngantry 0\nnrm 0 1 0\nvup 0 0 1\nisocenter 0 0 0\ncols 256\n"
                       "rows 256\nspacing 1 1\noffset 0 0\n"))
    << text;
}

TEST(DRRProjectionGeometryFileIO, WriteRefusesWhatCannotBeReadBack)
{
  const auto expectRefused = [](const GeometryType * geometry, const std::string & key) {
    std::ostringstream written;
    const std::string  message =
      ExceptionMessage([&] { IOType::WriteToStream(written, geometry); }, "writing a geometry with a bad " + key);
    EXPECT_TRUE(Contains(message, "DRRProjectionGeometryFileIO: ")) << message;
    EXPECT_TRUE(Contains(message, "'" + key + "'")) << message;
    EXPECT_EQ(written.str(), "") << "nothing is written when a value is refused";
  };
  auto geometry = GeometryType::New();
  geometry->SetSourceToDetectorDistance(std::numeric_limits<double>::infinity());
  expectRefused(geometry, "sid");
  geometry = GeometryType::New();
  geometry->SetDetectorOffset(Vec2(0.0, std::numeric_limits<double>::quiet_NaN()));
  expectRefused(geometry, "offset");
  geometry = GeometryType::New();
  geometry->SetDetectorSize({ { 0, 5 } });
  expectRefused(geometry, "cols");
  geometry = GeometryType::New();
  geometry->SetDetectorSize({ { 5, 1000001 } });
  expectRefused(geometry, "rows");

  std::ostringstream sink;
  EXPECT_THROW(IOType::WriteToStream(sink, nullptr), itk::ExceptionObject);
  std::istringstream source("sad 5");
  EXPECT_THROW(IOType::ReadFromStream(source, nullptr), itk::ExceptionObject);
  EXPECT_THROW(IOType::ParseLine("sad 5", nullptr), itk::ExceptionObject);
}

TEST(DRRProjectionGeometryFileIO, WriteAndReadFiles)
{
  // One directory per process: ctest runs the tests of this file in parallel.
  const std::filesystem::path directory =
    std::filesystem::temp_directory_path() / ("PointBasedDRRFileIOGTest-" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  const std::string fileName = (directory / "geometry.txt").string();

  auto geometry = GeometryType::New();
  geometry->SetGantryAngleInDegrees(-45.5);
  geometry->SetDetectorOffset(Vec2(1.0 / 3.0, -2.5));
  auto io = IOType::New();
  io->SetFileName(fileName);
  EXPECT_EQ(io->GetFileName(), fileName);
  ASSERT_NO_THROW(io->Write(geometry));

  // Read by the IO class and by DRRProjectionGeometry::ReadGeometryFile(), which calls it.
  auto readBack = MakeOtherGeometry();
  ASSERT_NO_THROW(io->Read(readBack));
  ExpectSameGeometry(readBack, geometry, "file read by DRRProjectionGeometryFileIO");
  readBack = MakeOtherGeometry();
  ASSERT_NO_THROW(readBack->ReadGeometryFile(fileName));
  ExpectSameGeometry(readBack, geometry, "file read by ReadGeometryFile()");

  // Write() replaces the file.
  geometry->SetSourceToIsocenterDistance(500.0);
  ASSERT_NO_THROW(io->Write(geometry));
  ASSERT_NO_THROW(io->Read(readBack));
  EXPECT_EQ(readBack->GetSourceToIsocenterDistance(), 500.0);

  // Errors: the messages of ReadGeometryFile(), and a file that cannot be written.
  io->SetFileName(directory.string());
  std::string message = ExceptionMessage([&] { io->Read(readBack); }, "reading a directory");
  EXPECT_EQ(message,
            "DRRProjectionGeometry: cannot read geometry file '" + directory.string() + "': it is a directory");
  message = ExceptionMessage([&] { io->Write(geometry); }, "writing a directory");
  EXPECT_EQ(message, "DRRProjectionGeometryFileIO: cannot write geometry file '" + directory.string() + "'");
  const std::string missing = (directory / "no such directory" / "geometry.txt").string();
  io->SetFileName(missing);
  message = ExceptionMessage([&] { io->Read(readBack); }, "reading a missing file");
  EXPECT_EQ(message, "DRRProjectionGeometry: cannot open geometry file '" + missing + "'");
  EXPECT_THROW(io->Write(geometry), itk::ExceptionObject);

  // A bad line names the file and the line; the lines before it are applied.
  {
    std::ofstream file(fileName);
    file << "# comment\nsad 123\n\nsid twelve\nsid 5\n";
  }
  io->SetFileName(fileName);
  readBack = MakeOtherGeometry();
  message = ExceptionMessage([&] { io->Read(readBack); }, "a bad line");
  EXPECT_EQ(message, "DRRProjectionGeometry: " + fileName + ":4: value 'twelve' of key 'sid' is not a finite number");
  EXPECT_EQ(readBack->GetSourceToIsocenterDistance(), 123.0);
  EXPECT_EQ(readBack->GetSourceToDetectorDistance(), 4.75);

  std::ostringstream printed;
  io->Print(printed);
  EXPECT_TRUE(Contains(printed.str(), "FileName: " + fileName)) << printed.str();
  std::filesystem::remove_all(directory);
}

TEST(DRRProjectionGeometryFileIO, ParseLineMessages)
{
  // The messages the format has always had (DRRProjectionGeometry: ...), with and without a location.
  auto       geometry = GeometryType::New();
  const auto message = [&](const std::string & line, const std::string & where = "") {
    return ExceptionMessage([&] { IOType::ParseLine(line, geometry, where); }, line);
  };
  EXPECT_EQ(message("cols 0", "f:2: "),
            "DRRProjectionGeometry: f:2: value '0' of key 'cols' must be a whole number in "
            "[1, 1e6]");
  EXPECT_EQ(message("rows 2.5"), "DRRProjectionGeometry: value '2.5' of key 'rows' must be a whole number in [1, 1e6]");
  EXPECT_EQ(message("rows 1e6x"), "DRRProjectionGeometry: value '1e6x' of key 'rows' is not a finite number");
  EXPECT_EQ(message("vup 1 2"), "DRRProjectionGeometry: key 'vup' takes 3 value(s), got 2");
  EXPECT_EQ(message("projection fan", "g:1: "),
            "DRRProjectionGeometry: g:1: projection must be 'perspective', 'parallel' or 'localizer', got 'fan'");
  EXPECT_EQ(message("nrm 0 0 0", "g:3: "),
            "DRRProjectionGeometry: g:3: key 'nrm': DRRProjectionGeometry: the normal (nrm) must be a finite, non-zero "
            "vector");
  EXPECT_EQ(message("focus 1"),
            "DRRProjectionGeometry: unknown key 'focus' (known: projection, sad, sid, gantry, nrm, "
            "vup, isocenter, cols, rows, spacing, offset, mirror)");
  EXPECT_EQ(message("mirror yes"), "DRRProjectionGeometry: mirror must be 0 or 1, got 'yes'");
  EXPECT_NO_THROW(IOType::ParseLine("rows 1000000 # the most", geometry));
  EXPECT_EQ(geometry->GetDetectorSize()[1], 1000000u);
}

// ---------------------------------------------------------------------------------------------------------------------
// The number parser shared by the geometry file and the pbdrr command line.

TEST(DRRNumberParser, AcceptsWholeFiniteNumbers)
{
  const struct
  {
    const char * text;
    double       value;
  } accepted[] = { { "0", 0.0 },
                   { "-2.5", -2.5 },
                   { "+7", 7.0 },
                   { "1e3", 1000.0 },
                   { "0x10", 16.0 },
                   { " 4", 4.0 },
                   { "1.7976931348623157e308", 1.7976931348623157e308 },
                   { "2.2250738585072014e-308", 2.2250738585072014e-308 } };
  for (const auto & c : accepted)
  {
    double value = -1.0;
    EXPECT_TRUE(itk::DRRNumberParser::ParseFiniteNumber(c.text, value)) << c.text;
    EXPECT_EQ(value, c.value) << c.text;
  }
  double negativeZero = 1.0;
  EXPECT_TRUE(itk::DRRNumberParser::ParseFiniteNumber("-0", negativeZero));
  EXPECT_TRUE(std::signbit(negativeZero));
}

TEST(DRRNumberParser, RefusesTheRestLeavingTheValue)
{
  for (const char * text : { "",
                             " ",
                             "x",
                             "1x",
                             "1 ",
                             "1,5",
                             "--1",
                             "inf",
                             "-inf",
                             "nan",
                             "infinity",
                             "1e309",
                             "-1e400",
                             "1e-320",
                             "0x",
                             "." })
  {
    double value = 42.0;
    EXPECT_FALSE(itk::DRRNumberParser::ParseFiniteNumber(text, value)) << "'" << text << "'";
    EXPECT_EQ(value, 42.0) << "'" << text << "'";
  }
}

TEST(DRRNumberParser, WholeNumbersInRange)
{
  EXPECT_TRUE(itk::DRRNumberParser::IsWholeNumberInRange(1.0, 1.0, 1e6));
  EXPECT_TRUE(itk::DRRNumberParser::IsWholeNumberInRange(1e6, 1.0, 1e6));
  EXPECT_FALSE(itk::DRRNumberParser::IsWholeNumberInRange(0.0, 1.0, 1e6));
  EXPECT_FALSE(itk::DRRNumberParser::IsWholeNumberInRange(1e6 + 1.0, 1.0, 1e6));
  EXPECT_FALSE(itk::DRRNumberParser::IsWholeNumberInRange(2.5, 1.0, 1e6));
  EXPECT_FALSE(itk::DRRNumberParser::IsWholeNumberInRange(std::nan(""), 1.0, 1e6));
}

// A -0 read over a geometry's +0 is kept (ITK's set macros skip a value equal to the one held, and -0 == 0): the
// geometry fuzzer's finding `offset 0 -0`, which read back as 0 0.
TEST(DRRProjectionGeometryFileIO, NegativeZeroOverZeroIsKept)
{
  auto               geometry = GeometryType::New();
  std::istringstream text("offset 0 -0\nisocenter -0 0 -0\nvup -0 -0 1\n");
  IOType::ReadFromStream(text, geometry);
  EXPECT_TRUE(std::signbit(geometry->GetDetectorOffset()[1]));
  EXPECT_FALSE(std::signbit(geometry->GetDetectorOffset()[0]));
  EXPECT_TRUE(std::signbit(geometry->GetIsocenter()[0]));
  EXPECT_TRUE(std::signbit(geometry->GetIsocenter()[2]));
  EXPECT_TRUE(std::signbit(geometry->GetViewUp()[0]));
  EXPECT_EQ(geometry->GetViewUp()[2], 1.0);
}
