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
// Tests of DRRRTKGeometryFileIO (RTK's ThreeDCircularProjectionGeometry XML). The convention is checked against RTK
// itself: against a file whose matrices RTK computed (test/data/rtk_geometry_documentation_example.xml, from RTK's
// documentation), and against RTK's matrix re-implemented here independently of the class, from RTK's source.

#include "gtest/gtest.h"

#include "PointBasedDRRTestHelpers.h"

#include "itkDRRRTKGeometryFileIO.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace
{
using PointBasedDRRTest::Contains;
using PointBasedDRRTest::ExceptionMessage;
using PointBasedDRRTest::Pt;
using PointBasedDRRTest::Vec;
using GeometryType = itk::DRRProjectionGeometry;
using IOType = itk::DRRRTKGeometryFileIO;
using ParametersType = IOType::ProjectionParameters;
using PointType = GeometryType::PointType;
using VectorType = GeometryType::VectorType;
using DetectorVectorType = GeometryType::DetectorVectorType;
using DirectionType = IOType::DetectorDirectionType;
using Matrix34 = std::array<std::array<double, 4>, 3>;

DetectorVectorType
Vec2(double a, double b)
{
  DetectorVectorType v;
  v[0] = a;
  v[1] = b;
  return v;
}

GeometryType::DetectorSizeType
Size2(itk::SizeValueType columns, itk::SizeValueType rows)
{
  GeometryType::DetectorSizeType size;
  size[0] = columns;
  size[1] = rows;
  return size;
}

DirectionType
Direction(double d00, double d01, double d10, double d11)
{
  DirectionType d;
  d[0][0] = d00;
  d[0][1] = d01;
  d[1][0] = d10;
  d[1][1] = d11;
  return d;
}

std::string
DataFile(const std::string & name)
{
  return std::string(POINTBASEDDRR_TEST_DATA_DIR) + "/" + name;
}

std::string
TemporaryFile(const std::string & name)
{
  // One directory per process: ctest runs the tests of this file in parallel.
  const std::filesystem::path directory =
    std::filesystem::temp_directory_path() / ("PointBasedDRRRTKGeometryGTest-" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  return (directory / name).string();
}

/** RTK's matrix, re-implemented here from RTK's source, independently of the class under test (no ITK transform, no
 * shared code): rtk::ThreeDCircularProjectionGeometry::AddProjectionInRadians() (src/rtkThreeDCircularProjection
 * Geometry.cxx) multiplies ComputeTranslationHomogeneousMatrix(sx - px, sy - py), ComputeProjectionMagnificationMatrix(
 * -sdd, -sid) (diag(-sdd, -sdd, 1) and -sid in the last column; parallel, sdd = 0: rows (1 0 0 0), (0 1 0 0),
 * (0 0 0 1)), ComputeTranslationHomogeneousMatrix(-sx, -sy, 0) and ComputeRotationHomogeneousMatrix(-oa, -ga, -ia),
 * itk::Euler3DTransform's ZXY order Rz Rx Ry; documentation/docs/Geometry.md, "Rotation Matrix" and "Final Matrix",
 * writes the same product. Angles in degrees, converted with atan(1) / 45 as RTK's AddProjection() does. */
Matrix34
ReferenceRTKMatrix(const ParametersType & p)
{
  const double degreesToRadians = std::atan(1.0) / 45.0;
  const double g = -p.GantryAngle * degreesToRadians;
  const double o = -p.OutOfPlaneAngle * degreesToRadians;
  const double i = -p.InPlaneAngle * degreesToRadians;
  const double rz[3][3] = { { std::cos(i), -std::sin(i), 0 }, { std::sin(i), std::cos(i), 0 }, { 0, 0, 1 } };
  const double rx[3][3] = { { 1, 0, 0 }, { 0, std::cos(o), -std::sin(o) }, { 0, std::sin(o), std::cos(o) } };
  const double ry[3][3] = { { std::cos(g), 0, std::sin(g) }, { 0, 1, 0 }, { -std::sin(g), 0, std::cos(g) } };
  double       rzx[3][3] = {};
  double       r[3][3] = {};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int k = 0; k < 3; ++k)
        rzx[a][b] += rz[a][k] * rx[k][b];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int k = 0; k < 3; ++k)
        r[a][b] += rzx[a][k] * ry[k][b];
  // The homogeneous map, applied to the columns of the 4 x 4 identity.
  Matrix34 m{};
  for (int column = 0; column < 4; ++column)
  {
    double x[3] = { 0, 0, 0 };
    double w = column == 3 ? 1.0 : 0.0;
    for (int a = 0; a < 3; ++a)
      x[a] = column < 3 ? r[a][column] : 0.0;
    x[0] -= p.SourceOffsetX * w;
    x[1] -= p.SourceOffsetY * w;
    const double sdd = p.SourceToDetectorDistance;
    double       q[3];
    if (sdd == 0.0)
    {
      q[0] = x[0];
      q[1] = x[1];
      q[2] = w;
    }
    else
    {
      q[0] = -sdd * x[0];
      q[1] = -sdd * x[1];
      q[2] = x[2] - p.SourceToIsocenterDistance * w;
    }
    q[0] += (p.SourceOffsetX - p.ProjectionOffsetX) * q[2];
    q[1] += (p.SourceOffsetY - p.ProjectionOffsetY) * q[2];
    for (int a = 0; a < 3; ++a)
      m[a][column] = q[a];
  }
  return m;
}

/** RTK's detector physical coordinates of a room point through an RTK matrix. */
std::array<double, 2>
ProjectRTK(const Matrix34 & m, const PointType & x)
{
  double q[3];
  for (int a = 0; a < 3; ++a)
    q[a] = m[a][0] * x[0] + m[a][1] * x[1] + m[a][2] * x[2] + m[a][3];
  return { q[0] / q[2], q[1] / q[2] };
}

/** The same through our geometry: GetProjectionMatrix() gives the pixel (i, j); RTK's projection image places it at
 * origin + D (i du, j dv). */
std::array<double, 2>
ProjectOurs(const GeometryType *       geometry,
            const PointType &          x,
            const DetectorVectorType & origin,
            const DirectionType &      d)
{
  const auto p = geometry->GetProjectionMatrix();
  double     q[3];
  for (int a = 0; a < 3; ++a)
    q[a] = p[a][0] * x[0] + p[a][1] * x[1] + p[a][2] * x[2] + p[a][3];
  const double i = q[0] / q[2] * geometry->GetDetectorSpacing()[0];
  const double j = q[1] / q[2] * geometry->GetDetectorSpacing()[1];
  return { origin[0] + d[0][0] * i + d[0][1] * j, origin[1] + d[1][0] * i + d[1][1] * j };
}

/** Room points around RTK's isocenter. */
std::vector<PointType>
RoomPoints()
{
  std::mt19937                           random(20261124);
  std::uniform_real_distribution<double> coordinate(-150.0, 150.0);
  std::vector<PointType>                 points{ Pt(0, 0, 0), Pt(100, 0, 0), Pt(0, 100, 0), Pt(0, 0, 100) };
  for (int k = 0; k < 12; ++k)
  {
    points.push_back(Pt(coordinate(random), coordinate(random), coordinate(random)));
  }
  return points;
}

/** Every room point goes to the same RTK detector point through RTK's matrix and through our geometry, to 1e-9
 * relative (to the coordinate, at least 1 mm). */
void
ExpectSameDetectorPoints(const Matrix34 &           rtk,
                         const GeometryType *       geometry,
                         const DetectorVectorType & origin,
                         const DirectionType &      d,
                         const std::string &        what)
{
  for (const auto & x : RoomPoints())
  {
    const auto expected = ProjectRTK(rtk, x);
    const auto actual = ProjectOurs(geometry, x, origin, d);
    for (int a = 0; a < 2; ++a)
    {
      EXPECT_NEAR(actual[a], expected[a], 1e-9 * std::max(1.0, std::abs(expected[a])))
        << what << ", room point " << x << ", detector axis " << a;
    }
  }
}

/** Two projection matrices equal to 1e-12 relative to their largest entry. */
void
ExpectSameProjectionMatrix(const GeometryType::ProjectionMatrixType & actual,
                           const GeometryType::ProjectionMatrixType & expected,
                           const std::string &                        what)
{
  double largest = 0.0;
  for (unsigned int r = 0; r < 3; ++r)
    for (unsigned int c = 0; c < 4; ++c)
      largest = std::max(largest, std::abs(expected[r][c]));
  for (unsigned int r = 0; r < 3; ++r)
    for (unsigned int c = 0; c < 4; ++c)
      EXPECT_NEAR(actual[r][c], expected[r][c], 1e-12 * largest) << what << ", entry (" << r << ", " << c << ")";
}

std::string
Number(double value)
{
  std::ostringstream text;
  text << std::setprecision(17) << value;
  return text.str();
}

/** An RTK geometry file written here (not by the class): every parameter in every projection, the Matrix from
 * ReferenceRTKMatrix(). */
std::string
ReferenceXML(const std::vector<ParametersType> & views)
{
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n<!DOCTYPE RTKGEOMETRY>\n<RTKThreeDCircularGeometry version=\"3\">\n";
  for (const auto & p : views)
  {
    xml << "  <Projection>\n"
        << "    <GantryAngle>" << Number(p.GantryAngle) << "</GantryAngle>\n"
        << "    <SourceToIsocenterDistance>" << Number(p.SourceToIsocenterDistance) << "</SourceToIsocenterDistance>\n"
        << "    <SourceToDetectorDistance>" << Number(p.SourceToDetectorDistance) << "</SourceToDetectorDistance>\n"
        << "    <SourceOffsetX>" << Number(p.SourceOffsetX) << "</SourceOffsetX>\n"
        << "    <SourceOffsetY>" << Number(p.SourceOffsetY) << "</SourceOffsetY>\n"
        << "    <ProjectionOffsetX>" << Number(p.ProjectionOffsetX) << "</ProjectionOffsetX>\n"
        << "    <ProjectionOffsetY>" << Number(p.ProjectionOffsetY) << "</ProjectionOffsetY>\n"
        << "    <InPlaneAngle>" << Number(p.InPlaneAngle) << "</InPlaneAngle>\n"
        << "    <OutOfPlaneAngle>" << Number(p.OutOfPlaneAngle) << "</OutOfPlaneAngle>\n"
        << "    <Matrix>\n";
    const Matrix34 m = ReferenceRTKMatrix(p);
    for (int r = 0; r < 3; ++r)
    {
      xml << "     ";
      for (int c = 0; c < 4; ++c)
        xml << ' ' << Number(m[r][c]);
      xml << '\n';
    }
    xml << "    </Matrix>\n  </Projection>\n";
  }
  xml << "</RTKThreeDCircularGeometry>\n";
  return xml.str();
}

ParametersType
Parameters(double gantry,
           double outOfPlane,
           double inPlane,
           double sid,
           double sourceX,
           double sourceY,
           double sdd,
           double projectionX,
           double projectionY)
{
  ParametersType p;
  p.GantryAngle = gantry;
  p.OutOfPlaneAngle = outOfPlane;
  p.InPlaneAngle = inPlane;
  p.SourceToIsocenterDistance = sid;
  p.SourceOffsetX = sourceX;
  p.SourceOffsetY = sourceY;
  p.SourceToDetectorDistance = sdd;
  p.ProjectionOffsetX = projectionX;
  p.ProjectionOffsetY = projectionY;
  return p;
}

/** Views with every parameter non-zero, some angles beyond 180 or negative. */
std::vector<ParametersType>
GeneralViews()
{
  return { Parameters(30.0, 12.0, -7.5, 1000.0, 15.0, -8.0, 1536.0, -40.0, 22.5),
           Parameters(271.847274780273, -20.0, 95.0, 800.0, -30.0, 12.0, 1200.0, 117.0, -1.0),
           Parameters(-135.25, 45.0, 181.0, 650.0, 5.5, 60.0, 1000.0, 3.0, 7.0),
           Parameters(400.0, 89.0, 33.0, 1200.0, 0.0, -45.0, 1800.0, 0.0, 80.0) };
}

IOType::GeometryListType
ReadText(const IOType * io, const std::string & text)
{
  std::istringstream stream(text);
  return io->ReadFromStream(stream, "test.xml");
}

std::string
ReadErrorOf(const std::string & text, const std::string & what)
{
  auto io = IOType::New();
  return ExceptionMessage([&] { ReadText(io, text); }, what);
}

std::string
WriteText(const IOType * io, const IOType::ConstGeometryListType & geometries)
{
  std::ostringstream text;
  io->WriteToStream(text, geometries);
  return text.str();
}

// ComputeRTKMatrix() is RTK's matrix: the class's product (through itk::Euler3DTransform, as RTK) and the independent
// re-implementation agree.
TEST(DRRRTKGeometryFileIO, ComputeRTKMatrixIsRTKsFormula)
{
  auto views = GeneralViews();
  views.push_back(Parameters(77.0, -33.0, 12.0, 900.0, 0.0, 0.0, 0.0, 5.0, -6.0)); // parallel
  for (const auto & p : views)
  {
    const auto     actual = IOType::ComputeRTKMatrix(p);
    const Matrix34 expected = ReferenceRTKMatrix(p);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(actual[r][c], expected[r][c], 1e-12 * 2000.0)
          << "gantry " << p.GantryAngle << " (" << r << ", " << c << ")";
  }
}

// Verified against RTK's documented convention, with matrices RTK itself computed: the example file of RTK's
// documentation. Every room point goes to the detector point RTK's stored Matrix gives.
TEST(DRRRTKGeometryFileIO, VerifiedAgainstRTKComputedFile)
{
  // The Matrix elements of test/data/rtk_geometry_documentation_example.xml, as RTK wrote them.
  const Matrix34 rtk[2] = { { { { -166.5093078829, 0, -1531.42837748039, -117056.503295898 },
                                { -1.01142410874151, -1536, 0.0326206557691505, -1011.95001602173 },
                                { -0.999480303105996, 0, 0.0322354417240802, -1000 } } },
                            { { { -166.660129424325, 0, -1531.41199650136, -117056.831359863 },
                                { -1.01134095059569, -1536, 0.0327174625589984, -1011.87002658844 },
                                { -0.999477130482326, 0, 0.0323336611415466, -1000 } } } };
  auto           io = IOType::New();
  io->SetFileName(DataFile("rtk_geometry_documentation_example.xml"));
  io->SetDetectorSize(Size2(512, 384));
  io->SetDetectorSpacing(Vec2(0.8, 0.75));
  const auto geometries = io->Read();
  ASSERT_EQ(geometries.size(), 2u);
  // The default origin: centred.
  const DetectorVectorType origin = Vec2(-0.5 * 511 * 0.8, -0.5 * 383 * 0.75);
  for (unsigned int v = 0; v < 2; ++v)
  {
    EXPECT_TRUE(geometries[v]->GetColumnsMirrored());
    EXPECT_EQ(geometries[v]->GetDetectorSize(), Size2(512, 384));
    // RTK's stored matrices hold 15 digits: they agree with the parameters to about 1e-13 relative.
    ExpectSameDetectorPoints(rtk[v], geometries[v], origin, io->GetDetectorDirection(), "view " + std::to_string(v));
    // RTK's source: (0, 0, SID) rotated back; the isocenter is the room origin.
    const auto source = geometries[v]->GetSourcePosition();
    EXPECT_NEAR(source.GetVectorFromOrigin().GetNorm(), 1000.0, 1e-9);
    EXPECT_NEAR(source[1], 0.0, 1e-9);
  }
  // The file as RTK's documentation has it, cylindrical detector and all, is refused.
  std::ifstream      file(DataFile("rtk_geometry_documentation_example.xml"));
  std::ostringstream text;
  text << file.rdbuf();
  std::string cylindrical = text.str();
  const auto  at = cylindrical.find("  <Projection>");
  cylindrical.insert(at, "  <RadiusCylindricalDetector>1536</RadiusCylindricalDetector>\n");
  const std::string message = ReadErrorOf(cylindrical, "cylindrical detector");
  EXPECT_TRUE(Contains(message, "projection 0")) << message;
  EXPECT_TRUE(Contains(message, "RadiusCylindricalDetector")) << message;
}

/** The Matrix elements of an RTK geometry file, parsed here (not by the class under test). */
std::vector<Matrix34>
MatricesInFile(const std::string & fileName)
{
  std::ifstream      file(fileName);
  std::ostringstream text;
  text << file.rdbuf();
  const std::string     xml = text.str();
  std::vector<Matrix34> matrices;
  for (auto at = xml.find("<Matrix>"); at != std::string::npos; at = xml.find("<Matrix>", at + 1))
  {
    std::istringstream numbers(xml.substr(at + 8, xml.find("</Matrix>", at) - at - 8));
    Matrix34           m{};
    for (int k = 0; k < 12; ++k)
    {
      numbers >> m[k / 4][k % 4];
    }
    EXPECT_FALSE(numbers.fail()) << fileName;
    matrices.push_back(m);
  }
  return matrices;
}

// Verified against RTK itself: files RTK's own writer wrote (rtk::WriteGeometry(), RTK's source compiled against
// Debian's ITK 5.2; see the comment in each file), views with every parameter non-zero (in-plane and out-of-plane
// angles, source and projection offsets) and parallel views. Every room point goes to the detector point of RTK's
// Matrix, through a centred grid and through a given origin with the rows reversed.
TEST(DRRRTKGeometryFileIO, VerifiedAgainstRTKWrittenFiles)
{
  for (const char * name : { "rtk_written_geometry.xml", "rtk_written_parallel_geometry.xml" })
  {
    const std::string fileName = DataFile(name);
    const auto        rtk = MatricesInFile(fileName);
    ASSERT_EQ(rtk.size(), Contains(name, "parallel") ? 2u : 4u) << name;
    for (const bool centred : { true, false })
    {
      auto io = IOType::New();
      io->SetFileName(fileName);
      io->SetDetectorSize(Size2(300, 200));
      io->SetDetectorSpacing(Vec2(0.7, 0.9));
      DetectorVectorType origin = Vec2(-0.5 * 299 * 0.7, -0.5 * 199 * 0.9);
      if (!centred)
      {
        io->SetDetectorDirection(Direction(1, 0, 0, -1));
        origin = Vec2(-100.0, 90.0);
        io->SetDetectorOrigin(origin);
      }
      const auto geometries = io->Read();
      ASSERT_EQ(geometries.size(), rtk.size());
      for (size_t v = 0; v < rtk.size(); ++v)
      {
        EXPECT_EQ(geometries[v]->GetColumnsMirrored(), centred) << name;
        ExpectSameDetectorPoints(rtk[v],
                                 geometries[v],
                                 origin,
                                 io->GetDetectorDirection(),
                                 std::string(name) + " view " + std::to_string(v) + (centred ? "" : ", rows reversed"));
      }
    }
  }
}

// Verified against RTK's formula (the independent re-implementation) with every parameter non-zero: in-plane and
// out-of-plane angles, source and projection offsets; with the centred origin, a given origin, and a projection
// direction that flips and swaps the axes.
TEST(DRRRTKGeometryFileIO, VerifiedAgainstRTKFormulaAllParameters)
{
  const auto views = GeneralViews();
  const auto xml = ReferenceXML(views);
  struct Grid
  {
    DirectionType      D;
    bool               Centred;
    DetectorVectorType Origin;
  };
  const Grid grids[] = { { Direction(1, 0, 0, 1), true, Vec2(0, 0) },
                         { Direction(1, 0, 0, 1), false, Vec2(-123.25, 40.5) },
                         { Direction(1, 0, 0, -1), true, Vec2(0, 0) },
                         { Direction(0, 1, 1, 0), false, Vec2(17.0, -250.0) },
                         { Direction(0, -1, 1, 0), true, Vec2(0, 0) } };
  for (const auto & grid : grids)
  {
    auto io = IOType::New();
    io->SetDetectorSize(Size2(300, 200));
    io->SetDetectorSpacing(Vec2(0.5, 1.25));
    io->SetDetectorDirection(grid.D);
    if (!grid.Centred)
    {
      io->SetDetectorOrigin(grid.Origin);
    }
    EXPECT_EQ(io->GetDetectorOriginCentered(), grid.Centred);
    const auto geometries = ReadText(io, xml);
    ASSERT_EQ(geometries.size(), views.size());
    DetectorVectorType origin = grid.Origin;
    if (grid.Centred)
    {
      const double hc = 0.5 * 299 * 0.5;
      const double hr = 0.5 * 199 * 1.25;
      origin = Vec2(-(grid.D[0][0] * hc + grid.D[0][1] * hr), -(grid.D[1][0] * hc + grid.D[1][1] * hr));
    }
    for (size_t v = 0; v < views.size(); ++v)
    {
      std::ostringstream what;
      what << "view " << v << ", direction " << grid.D[0][0] << " " << grid.D[0][1] << " " << grid.D[1][0] << " "
           << grid.D[1][1];
      ExpectSameDetectorPoints(ReferenceRTKMatrix(views[v]), geometries[v], origin, grid.D, what.str());
      // The pixel centres lie on RTK's detector plane, SID - SDD along RTK's normal from its isocenter.
      const Matrix34 m = ReferenceRTKMatrix(views[v]);
      const auto     pixel = geometries[v]->GetPixelCenter(17.0, 5.0);
      const double   depth = m[2][0] * pixel[0] + m[2][1] * pixel[1] + m[2][2] * pixel[2] + m[2][3];
      EXPECT_NEAR(depth, -views[v].SourceToDetectorDistance, 1e-9) << what.str();
    }
  }
}

// A parallel view (SourceToDetectorDistance 0, RTK's default): parallel beams along RTK's normal, the detector plane
// SID behind RTK's isocenter.
TEST(DRRRTKGeometryFileIO, VerifiedAgainstRTKFormulaParallel)
{
  const std::vector<ParametersType> views = { Parameters(10.0, 20.0, 30.0, 700.0, 0.0, 0.0, 0.0, 12.0, -3.0),
                                              Parameters(250.0, -5.0, 0.0, 700.0, 0.0, 0.0, 0.0, -8.0, 44.0) };
  // RTK's writer omits SourceToDetectorDistance 0: remove it from the reference file too.
  std::string xml = ReferenceXML(views);
  for (std::string::size_type at;
       (at = xml.find("    <SourceToDetectorDistance>0</SourceToDetectorDistance>\n")) != std::string::npos;)
  {
    xml.erase(at, std::string("    <SourceToDetectorDistance>0</SourceToDetectorDistance>\n").size());
  }
  auto io = IOType::New();
  io->SetDetectorSize(Size2(64, 48));
  io->SetDetectorSpacing(Vec2(2.0, 3.0));
  const auto geometries = ReadText(io, xml);
  ASSERT_EQ(geometries.size(), 2u);
  for (size_t v = 0; v < views.size(); ++v)
  {
    EXPECT_EQ(geometries[v]->GetProjection(), GeometryType::ProjectionEnum::Parallel);
    ExpectSameDetectorPoints(
      ReferenceRTKMatrix(views[v]), geometries[v], Vec2(-31.5 * 2.0, -23.5 * 3.0), Direction(1, 0, 0, 1), "parallel");
    const auto plane = geometries[v]->GetDetectorPlaneOrigin().GetVectorFromOrigin();
    EXPECT_NEAR(plane * geometries[v]->GetNormal(), -700.0, 1e-9);
  }
}

// RTK does not forbid a detector nearer the source than the isocenter (SDD < SID): it maps exactly too.
TEST(DRRRTKGeometryFileIO, DetectorBetweenSourceAndIsocenter)
{
  const std::vector<ParametersType> views = { Parameters(40.0, 5.0, 10.0, 1000.0, 3.0, 4.0, 600.0, 1.0, 2.0) };
  auto                              io = IOType::New();
  const auto                        geometries = ReadText(io, ReferenceXML(views));
  ASSERT_EQ(geometries.size(), 1u);
  ExpectSameDetectorPoints(
    ReferenceRTKMatrix(views[0]), geometries[0], Vec2(-127.5, -127.5), Direction(1, 0, 0, 1), "SDD < SID");
}

// A gantry sweep in our convention, written then read back: the same projection matrices.
TEST(DRRRTKGeometryFileIO, GantrySweepRoundTrip)
{
  for (const bool mirrored : { true, false })
  {
    IOType::ConstGeometryListType sweep;
    for (double angle = -180.0; angle < 360.0; angle += 7.5)
    {
      auto geometry = GeometryType::New();
      geometry->SetGantryAngleInDegrees(angle + 0.125);
      geometry->SetColumnsMirrored(mirrored);
      geometry->SetIsocenter(Pt(12.5, -30.0, 7.0));
      geometry->SetDetectorSize(Size2(320, 240));
      geometry->SetDetectorSpacing(Vec2(0.6, 0.9));
      geometry->SetDetectorOffset(Vec2(14.0, -3.5));
      geometry->VerifyGeometry();
      sweep.push_back(geometry.GetPointer());
    }
    const std::string fileName = TemporaryFile(mirrored ? "sweep_mirrored.xml" : "sweep.xml");
    auto              io = IOType::New();
    io->SetFileName(fileName);
    io->SetDetectorSize(Size2(320, 240));
    io->SetDetectorSpacing(Vec2(0.6, 0.9));
    // Not mirrored: RTK's projection image has its rows reversed.
    io->SetDetectorDirection(mirrored ? Direction(1, 0, 0, 1) : Direction(1, 0, 0, -1));
    io->Write(sweep);
    EXPECT_FALSE(std::filesystem::exists(fileName + ".tmp"));
    const auto back = io->Read();
    ASSERT_EQ(back.size(), sweep.size());
    for (size_t v = 0; v < sweep.size(); ++v)
    {
      EXPECT_EQ(back[v]->GetColumnsMirrored(), mirrored);
      ExpectSameProjectionMatrix(
        back[v]->GetProjectionMatrix(), sweep[v]->GetProjectionMatrix(), "sweep view " + std::to_string(v));
      EXPECT_LT((back[v]->GetSourcePosition() - sweep[v]->GetSourcePosition()).GetNorm(), 1e-9);
    }
    // The file holds what RTK's reader reads: its own Matrix check passes on re-reading (done by Read()), and the
    // shared values are written once.
    std::ifstream      file(fileName);
    std::ostringstream text;
    text << file.rdbuf();
    EXPECT_TRUE(Contains(text.str(), "<RTKThreeDCircularGeometry version=\"3\">")) << text.str();
    EXPECT_TRUE(Contains(text.str(), "  <SourceToDetectorDistance>1500</SourceToDetectorDistance>\n")) << text.str();
  }
}

// Random geometries of every kind RTK can hold (perspective and parallel, any orientation, mirrored or not with a
// matching direction, offsets, isocenters, origins) written and read back; and RTK's parameters through
// MakeGeometry() and ComputeParameters() give back the same matrix.
TEST(DRRRTKGeometryFileIO, RandomRoundTrips)
{
  std::mt19937                           random(424242);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    auto geometry = GeometryType::New();
    geometry->SetProjection(trial % 4 == 3 ? GeometryType::ProjectionEnum::Parallel
                                           : GeometryType::ProjectionEnum::Perspective);
    VectorType normal;
    do
    {
      normal = Vec(unit(random), unit(random), unit(random));
    } while (normal.GetNorm() < 0.1);
    if (trial == 0)
    {
      normal = Vec(0, 1, 0); // out-of-plane angle -90: gimbal lock
    }
    if (trial == 1)
    {
      normal = Vec(0, -1, 0);
    }
    geometry->SetNormal(normal);
    geometry->SetViewUp(Vec(unit(random), unit(random), unit(random)));
    const bool mirrored = fraction(random) < 0.5;
    geometry->SetColumnsMirrored(mirrored);
    geometry->SetIsocenter(Pt(40 * unit(random), 40 * unit(random), 40 * unit(random)));
    geometry->SetSourceToIsocenterDistance(500.0 + 1000.0 * fraction(random));
    // (A parallel view's detector plane stays behind RTK's isocenter, the room origin: RTK's SID is positive.)
    geometry->SetSourceToDetectorDistance(geometry->GetSourceToIsocenterDistance() + 100.0 + 1000.0 * fraction(random));
    const auto size = Size2(1 + static_cast<itk::SizeValueType>(600 * fraction(random)),
                            1 + static_cast<itk::SizeValueType>(600 * fraction(random)));
    geometry->SetDetectorSize(size);
    geometry->SetDetectorSpacing(Vec2(0.1 + 2.0 * fraction(random), 0.1 + 2.0 * fraction(random)));
    geometry->SetDetectorOffset(Vec2(100 * unit(random), 100 * unit(random)));
    ASSERT_NO_THROW(geometry->VerifyGeometry());

    auto io = IOType::New();
    io->SetDetectorSize(size);
    io->SetDetectorSpacing(geometry->GetDetectorSpacing());
    // A direction of the handedness the view needs: a rotation by a multiple of 90 degrees, reflected if not
    // mirrored.
    const int     quarter = static_cast<int>(4 * fraction(random)) % 4;
    const double  c = quarter == 0 ? 1 : quarter == 2 ? -1 : 0;
    const double  s = quarter == 1 ? 1 : quarter == 3 ? -1 : 0;
    DirectionType d = Direction(c, -s, s, c);
    if (!mirrored)
    {
      d = Direction(c, s, s, -c);
    }
    io->SetDetectorDirection(d);
    if (trial % 3 == 0)
    {
      io->SetDetectorOrigin(Vec2(300 * unit(random), 300 * unit(random)));
    }
    const std::string text = WriteText(io, { geometry.GetPointer() });
    const auto        back = ReadText(io, text);
    ASSERT_EQ(back.size(), 1u);
    ExpectSameProjectionMatrix(
      back[0]->GetProjectionMatrix(), geometry->GetProjectionMatrix(), "random trial " + std::to_string(trial));
    EXPECT_EQ(back[0]->GetProjection(), geometry->GetProjection());

    // Parameters to geometry to parameters: the same RTK matrix.
    const ParametersType p = io->ComputeParameters(geometry);
    const ParametersType q = io->ComputeParameters(io->MakeGeometry(p));
    const auto           mp = IOType::ComputeRTKMatrix(p);
    const auto           mq = IOType::ComputeRTKMatrix(q);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(mq[r][k], mp[r][k], 1e-9 * std::max(1.0, std::abs(mp[r][k]))) << "trial " << trial;
  }
}

// What RTK cannot hold, or what would come out wrong, is refused on writing, and nothing is written.
TEST(DRRRTKGeometryFileIO, WriteRefusals)
{
  auto io = IOType::New();
  auto good = GeometryType::New();
  good->SetColumnsMirrored(true);

  EXPECT_TRUE(Contains(ExceptionMessage([&] { WriteText(io, {}); }, "empty"), "no geometry"));
  EXPECT_TRUE(Contains(ExceptionMessage([&] { WriteText(io, { nullptr }); }, "null"), "null"));

  auto localizer = GeometryType::New();
  localizer->SetProjection(GeometryType::ProjectionEnum::Localizer);
  localizer->SetColumnsMirrored(true);
  std::string message = ExceptionMessage([&] { WriteText(io, { good.GetPointer(), localizer.GetPointer() }); }, "loc");
  EXPECT_TRUE(Contains(message, "geometry 1")) << message;
  EXPECT_TRUE(Contains(message, "localizer")) << message;

  auto notMirrored = GeometryType::New();
  message = ExceptionMessage([&] { WriteText(io, { notMirrored.GetPointer() }); }, "handedness");
  EXPECT_TRUE(Contains(message, "left-handed")) << message;
  EXPECT_TRUE(Contains(message, "ColumnsMirrored")) << message;

  auto behind = GeometryType::New();
  behind->SetColumnsMirrored(true);
  behind->SetIsocenter(Pt(-2000.0, 0.0, 0.0)); // the room origin behind the source
  message = ExceptionMessage([&] { WriteText(io, { behind.GetPointer() }); }, "behind");
  EXPECT_TRUE(Contains(message, "SourceToIsocenterDistance")) << message;

  auto parallel = GeometryType::New();
  parallel->SetProjection(GeometryType::ProjectionEnum::Parallel);
  parallel->SetColumnsMirrored(true);
  message = ExceptionMessage([&] { WriteText(io, { good.GetPointer(), parallel.GetPointer() }); }, "mixed");
  EXPECT_TRUE(Contains(message, "parallel and divergent")) << message;

  auto invalid = GeometryType::New();
  invalid->SetSourceToIsocenterDistance(-1.0);
  EXPECT_FALSE(ExceptionMessage([&] { WriteText(io, { invalid.GetPointer() }); }, "invalid").empty());

  io->SetDetectorDirection(Direction(1, 1, 0, 1));
  EXPECT_TRUE(
    Contains(ExceptionMessage([&] { WriteText(io, { good.GetPointer() }); }, "skewed direction"), "orthogonal"));
  io->SetDetectorDirection(Direction(1, 0, 0, 1));

  // A refused write leaves the file as it was, and no temporary beside it.
  const std::string fileName = TemporaryFile("kept.xml");
  io->SetFileName(fileName);
  io->Write({ good.GetPointer() });
  std::ifstream      before(fileName);
  std::ostringstream kept;
  kept << before.rdbuf();
  before.close();
  EXPECT_FALSE(ExceptionMessage([&] { io->Write({ localizer.GetPointer() }); }, "refused write").empty());
  std::ifstream      after(fileName);
  std::ostringstream now;
  now << after.rdbuf();
  EXPECT_EQ(now.str(), kept.str());
  EXPECT_FALSE(std::filesystem::exists(fileName + ".tmp"));

  io->SetFileName(TemporaryFile("no-such-directory/geometry.xml"));
  EXPECT_TRUE(Contains(ExceptionMessage([&] { io->Write({ good.GetPointer() }); }, "unwritable"), "cannot write"));
  io->SetFileName(std::filesystem::path(fileName).parent_path().string());
  EXPECT_TRUE(Contains(ExceptionMessage([&] { io->Write({ good.GetPointer() }); }, "directory"), "directory"));
}

/** A valid one-projection file with a replacement applied to it. */
std::string
OneView(const std::string & from = "", const std::string & to = "")
{
  std::string xml = ReferenceXML({ Parameters(30.0, 12.0, -7.5, 1000.0, 15.0, -8.0, 1536.0, -40.0, 22.5),
                                   Parameters(60.0, 12.0, -7.5, 1000.0, 15.0, -8.0, 1536.0, -40.0, 22.5) });
  if (!from.empty())
  {
    // The replacement applies to the second projection (index 1).
    const auto second = xml.find("<Projection>", xml.find("<Projection>") + 1);
    const auto at = xml.find(from, second);
    EXPECT_NE(at, std::string::npos) << from;
    xml.replace(at, from.size(), to);
  }
  return xml;
}

/** Elements nested depth deep: <n><n>...</n></n> (an unknown element, ignored where it is not too deep). */
std::string
Nested(unsigned int depth)
{
  std::string xml;
  for (unsigned int i = 0; i < depth; ++i)
  {
    xml += "<n>";
  }
  for (unsigned int i = 0; i < depth; ++i)
  {
    xml += "</n>";
  }
  return xml;
}

// Bad input: each a clear itk::ExceptionObject naming the problem (and the projection), never a crash.
TEST(DRRRTKGeometryFileIO, BadInput)
{
  ASSERT_NO_THROW(ReadText(IOType::New(), OneView()));

  auto io = IOType::New();
  io->SetFileName(TemporaryFile("does-not-exist.xml"));
  EXPECT_TRUE(Contains(ExceptionMessage([&] { io->Read(); }, "missing file"), "cannot open"));
  io->SetFileName(std::filesystem::temp_directory_path().string());
  EXPECT_TRUE(Contains(ExceptionMessage([&] { io->Read(); }, "directory"), "directory"));

  struct Case
  {
    std::string Text;
    std::string Expected[2];
  };
  const std::string valid = OneView();
  std::string       noMatrix = OneView("<Matrix>", "<Matrice>"); // an unknown element, ignored
  noMatrix.replace(noMatrix.find("</Matrix>", noMatrix.find("<Matrice>")), 9, "</Matrice>");
  const Case cases[] = {
    { "", { "no root element", "" } },
    { "hello, world\n", { "not an XML document", "expat: syntax error" } },
    { "\x89PNG\r\n\x1a\n", { "not an XML document", "" } },
    { valid.substr(0, valid.size() / 2), { "truncated", "" } },
    { valid.substr(0, valid.size() - 3), { "truncated", "" } },
    { valid + "<extra/>", { "after the root", "" } },
    { "<?xml version=\"1.0\"?>\n<Geometry version=\"3\"><Projection/></Geometry>",
      { "root element is <Geometry>", "" } },
    { "<RTKThreeDCircularGeometry><Projection/></RTKThreeDCircularGeometry>", { "no version", "" } },
    { "<RTKThreeDCircularGeometry version=\"4\"></RTKThreeDCircularGeometry>", { "version \"4\"", "" } },
    { "<RTKThreeDCircularGeometry version=\"3\">\n</RTKThreeDCircularGeometry>", { "no <Projection>", "" } },
    { OneView("<GantryAngle>60</GantryAngle>", ""), { "projection 1", "no <GantryAngle>" } },
    { noMatrix, { "projection 1", "no <Matrix>" } },
    { OneView("<SourceToIsocenterDistance>1000<", "<SourceToIsocenterDistance>nan<"),
      { "projection 1", "<SourceToIsocenterDistance> 'nan' is not a finite number" } },
    { OneView("<ProjectionOffsetX>-40<", "<ProjectionOffsetX>inf<"), { "projection 1", "ProjectionOffsetX" } },
    { OneView("<InPlaneAngle>-7.5<", "<InPlaneAngle>1e999<"), { "projection 1", "InPlaneAngle" } },
    { OneView("<SourceOffsetX>15<", "<SourceOffsetX>15 mm<"), { "projection 1", "SourceOffsetX" } },
    { OneView("<SourceToIsocenterDistance>1000<", "<SourceToIsocenterDistance>-1000<"),
      { "projection 1", "SourceToIsocenterDistance -1000 is not positive" } },
    { OneView("<SourceToIsocenterDistance>1000<", "<SourceToIsocenterDistance>0<"),
      { "projection 1", "SourceToIsocenterDistance 0 is not positive" } },
    { OneView("<SourceToDetectorDistance>1536<", "<SourceToDetectorDistance>-1536<"),
      { "projection 1", "SourceToDetectorDistance -1536 is negative" } },
    { OneView("<SourceToDetectorDistance>1536<", "<SourceToDetectorDistance>0<"),
      { "projection 1", "RTK does not mix them" } },
    { OneView("<Matrix>\n      ", "<Matrix>\n      nan "), { "projection 1", "<Matrix> entry 'nan'" } },
    { OneView("<Matrix>\n      ", "<Matrix>\n      1 "), { "projection 1", "<Matrix> has 13 numbers" } },
    { OneView("<GantryAngle>60<", "<GantryAngle>60.01<"), { "projection 1", "is not the" } },
    { OneView("</Matrix>", "</Matrixx>"),
      { "mismatched tag", "in /RTKThreeDCircularGeometry/Projection[2]/Matrix[1]" } },
    { OneView("<GantryAngle>60<", "<GantryAngle>&foo;60<"),
      { "undefined entity", "in /RTKThreeDCircularGeometry/Projection[2]/GantryAngle[1]" } },
    // Depth 2 + 31: one deeper than DRRDOMNodeXMLReader::GetMaximumDepth() (RTKReaderRules reads depth 32).
    { OneView("<Matrix>", Nested(31) + "<Matrix>"), { "nested more than 32 deep", "" } },
    { OneView("<Matrix>", "<RadiusCylindricalDetector>1536</RadiusCylindricalDetector><Matrix>"),
      { "projection 1", "cylindrical detector" } },
    { OneView("<Matrix>", "<CollimationUInf>20</CollimationUInf><Matrix>"), { "projection 1", "CollimationUInf" } },
    { OneView("<Projection>", "<Projection a>"), { "not well-formed (invalid token)", "" } },
  };
  for (const auto & c : cases)
  {
    const std::string message = ReadErrorOf(c.Text, c.Text.substr(0, 80));
    for (const auto & expected : c.Expected)
    {
      EXPECT_TRUE(Contains(message, expected)) << "'" << expected << "' not in: " << message;
    }
    EXPECT_TRUE(message.empty() || Contains(message, "test.xml")) << message;
  }
  // A file is named in its errors.
  const std::string fileName = TemporaryFile("truncated.xml");
  std::ofstream(fileName) << valid.substr(0, 200);
  io->SetFileName(fileName);
  const std::string message = ExceptionMessage([&] { io->Read(); }, "truncated file");
  EXPECT_TRUE(Contains(message, fileName)) << message;
  EXPECT_TRUE(Contains(message, "truncated")) << message;

  // Invalid settings of the detector grid.
  auto badGrid = IOType::New();
  badGrid->SetDetectorSpacing(Vec2(0.0, 1.0));
  EXPECT_TRUE(Contains(ExceptionMessage([&] { ReadText(badGrid, valid); }, "zero spacing"), "projection 0"));
  badGrid->SetDetectorSpacing(Vec2(1.0, 1.0));
  badGrid->SetDetectorSize(Size2(0, 10));
  EXPECT_TRUE(Contains(ExceptionMessage([&] { ReadText(badGrid, valid); }, "zero size"), "zero columns"));
}

// RTK's reader's rules: names without case, the old name Angle, globals shared by the projections after them, values
// carried from one projection to the next, unknown elements and comments ignored.
TEST(DRRRTKGeometryFileIO, RTKReaderRules)
{
  const ParametersType p0 = Parameters(30.0, 0.0, 0.0, 900.0, 0.0, 0.0, 1400.0, 0.0, 0.0);
  ParametersType       p1 = p0;
  p1.GantryAngle = 45.0;
  p1.ProjectionOffsetX = 5.0;
  ParametersType p2 = p1; // RTK carries ProjectionOffsetX over
  p2.GantryAngle = 50.0;
  const auto matrixText = [](const ParametersType & p) {
    std::ostringstream text;
    const Matrix34     m = ReferenceRTKMatrix(p);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        text << ' ' << Number(m[r][c]);
    return text.str();
  };
  std::ostringstream xml;
  xml << "<?xml version='1.0'?><!-- a comment --><RTKThreeDCircularGeometry version='2'>"
      << "<sourcetoisocenterdistance> 900 </sourcetoisocenterdistance><SourceToDetectorDistance>1400"
      << "</SourceToDetectorDistance><Unknown>x</Unknown>" << Nested(31) << "<Projection><Angle>30</Angle><Matrix>"
      << matrixText(p0) << "</Matrix></Projection>"
      << "<Projection><GantryAngle>45</GantryAngle><ProjectionOffsetX>5</ProjectionOffsetX><Matrix>" << matrixText(p1)
      << "</Matrix></Projection>"
      << "<Projection><GantryAngle>5&#48;</GantryAngle><Matrix>" << matrixText(p2) << "</Matrix></Projection>"
      << "</RTKThreeDCircularGeometry>";
  auto       io = IOType::New();
  const auto geometries = ReadText(io, xml.str());
  ASSERT_EQ(geometries.size(), 3u);
  const ParametersType expected[] = { p0, p1, p2 };
  for (int v = 0; v < 3; ++v)
  {
    ExpectSameDetectorPoints(ReferenceRTKMatrix(expected[v]),
                             geometries[v],
                             Vec2(-127.5, -127.5),
                             Direction(1, 0, 0, 1),
                             "view " + std::to_string(v));
  }
}

TEST(DRRRTKGeometryFileIO, SettersAndPrint)
{
  auto io = IOType::New();
  EXPECT_EQ(io->GetDetectorSize(), Size2(256, 256));
  EXPECT_EQ(io->GetDetectorSpacing(), Vec2(1.0, 1.0));
  EXPECT_TRUE(io->GetDetectorOriginCentered());
  EXPECT_EQ(io->GetDetectorDirection(), Direction(1, 0, 0, 1));
  io->SetDetectorOrigin(Vec2(1.0, 2.0));
  EXPECT_FALSE(io->GetDetectorOriginCentered());
  EXPECT_EQ(io->GetDetectorOrigin(), Vec2(1.0, 2.0));
  io->DetectorOriginCenteredOn();
  EXPECT_TRUE(io->GetDetectorOriginCentered());
  io->SetFileName("geometry.xml");
  std::ostringstream printed;
  io->Print(printed);
  EXPECT_TRUE(Contains(printed.str(), "FileName: geometry.xml")) << printed.str();
  EXPECT_TRUE(Contains(printed.str(), "DetectorOriginCentered: On")) << printed.str();
}
} // namespace
