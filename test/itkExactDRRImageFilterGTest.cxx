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

// Tests of itk::ExactDRRImageFilter against closed-form line integrals written here, independently of the
// module's own integrator (DRRExactRayIntegrator) and projection mapping (DRRPointProjection):
//
// - Box model: a block of constant voxels low..high is the oriented physical box
//   {origin + D diag(spacing) p : p in [low - 0.5, high + 0.5]^3}; the line integral is mu times the length of the
//   ray segment inside it, computed with the slab method on the box's own axes (columns of D), centre and
//   half-extents.
// - Tent model: the trilinear interpolant of the zero-padded volume; for a constant block it is
//   mu T_x(p_x) T_y(p_y) T_z(p_z) in continuous index coordinates p, with T_a the trapezoid that is 1 on
//   [low_a, high_a] and ramps to 0 at low_a - 1 and high_a + 1. Along a ray this is a piecewise cubic with
//   breakpoints where p_a crosses low_a - 1, low_a, high_a, high_a + 1; each piece is integrated with 3-point
//   Gauss-Legendre (exact to degree 5).
//
// A perspective ray runs from the source to the pixel centre; a parallel ray is the whole line through the pixel
// centre along the detector normal. With a transform T (room -> volume frame), the room segment A..B is mapped to
// T(A)..T(B): a linear T preserves the ray parameter, so the room line integral is |B - A| times the integral of mu
// over the parameter t in [0, 1].

#include "itkExactDRRImageFilter.h"
#include "itkCommand.h"
#include "itkDRRPolicies.h"
#include "itkAffineTransform.h"
#include "itkEuler3DTransform.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace
{
using PointBasedDRRTest::MuVolumeType;
using OutputImageType = itk::Image<double, 2>;
using FilterType = itk::ExactDRRImageFilter<MuVolumeType, OutputImageType>;
using GeometryType = itk::DRRProjectionGeometry;
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
using ProjectionEnum = itk::PointBasedDRREnums::Projection;
using OutputModeEnum = itk::PointBasedDRREnums::OutputMode;
using TransferEnum = itk::PointBasedDRREnums::TransferFunction;
using PointType = itk::Point<double, 3>;
using VectorType = itk::Vector<double, 3>;
using MatrixType = itk::Matrix<double, 3, 3>;
using TransformType = itk::Transform<double, 3, 3>;

/** Half-length (mm) of the segment standing for the infinite parallel ray: far beyond every test volume. */
constexpr double kParallelHalfLength = 2000.0;
/** Relative tolerance, and the absolute one where the reference is ~0. */
constexpr double kRelativeTolerance = 1e-6;
constexpr double kAbsoluteTolerance = 1e-9;

const KernelEnum     kKernels[] = { KernelEnum::Box, KernelEnum::Tent };
const ProjectionEnum kProjections[] = { ProjectionEnum::Perspective,
                                        ProjectionEnum::Parallel,
                                        ProjectionEnum::Localizer };

std::string
Name(KernelEnum kernel)
{
  return kernel == KernelEnum::Box ? "box" : "tent";
}

std::string
Name(ProjectionEnum projection)
{
  return itk::DRRPolicies::Beams::GetName(projection);
}

/** A volume whose voxels low..high (inclusive, per axis) hold mu and all others 0. */
struct BlockPhantom
{
  itk::Size<3>  size{ { 1, 1, 1 } };
  VectorType    spacing{ 1.0 };
  PointType     origin{ 0.0 };
  MatrixType    direction{ MatrixType::GetIdentity() };
  itk::Index<3> low{ { 0, 0, 0 } };
  itk::Index<3> high{ { 0, 0, 0 } };
  double        mu{ 0.0 };

  MuVolumeType::Pointer
  MakeVolume() const
  {
    MuVolumeType::SpacingType imageSpacing;
    for (unsigned int a = 0; a < 3; ++a)
    {
      imageSpacing[a] = spacing[a];
    }
    auto volume = PointBasedDRRTest::MakeVolume<MuVolumeType>(size, imageSpacing, origin, direction);
    PointBasedDRRTest::FillBlock<MuVolumeType>(volume.GetPointer(), low, high, static_cast<float>(mu));
    return volume;
  }

  /** The value the filter sees (the voxels are float). */
  double
  StoredMu() const
  {
    return static_cast<double>(static_cast<float>(mu));
  }

  /** D diag(spacing): continuous index -> physical (minus the origin). */
  MatrixType
  IndexToPhysical() const
  {
    MatrixType m;
    for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int c = 0; c < 3; ++c)
      {
        m[r][c] = direction[r][c] * spacing[c];
      }
    }
    return m;
  }

  /** Physical point of a continuous index. */
  PointType
  PhysicalPoint(const std::array<double, 3> & index) const
  {
    const MatrixType m = this->IndexToPhysical();
    PointType        x = origin;
    for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int c = 0; c < 3; ++c)
      {
        x[r] += m[r][c] * index[c];
      }
    }
    return x;
  }

  PointType
  BlockCentre() const
  {
    std::array<double, 3> centre;
    for (unsigned int a = 0; a < 3; ++a)
    {
      centre[a] = 0.5 * static_cast<double>(low[a] + high[a]);
    }
    return this->PhysicalPoint(centre);
  }
};

/** The phantom's grid with its centre (of the voxel-centre range) at centre. */
void
CentreVolumeAt(BlockPhantom & phantom, const PointType & centre)
{
  std::array<double, 3> middle;
  for (unsigned int a = 0; a < 3; ++a)
  {
    middle[a] = 0.5 * (static_cast<double>(phantom.size[a]) - 1.0);
  }
  phantom.origin.Fill(0.0);
  const PointType shifted = phantom.PhysicalPoint(middle);
  for (unsigned int r = 0; r < 3; ++r)
  {
    phantom.origin[r] = centre[r] - shifted[r];
  }
}

/** Independent closed-form line integrals through a BlockPhantom, optionally moved by a room -> volume transform. */
class ClosedFormReference
{
public:
  ClosedFormReference(const BlockPhantom & phantom, const TransformType * transform)
    : m_Phantom(phantom), m_Transform(transform)
  {
    m_IndexToPhysical = phantom.IndexToPhysical();
    m_PhysicalToIndex = MatrixType(m_IndexToPhysical.GetInverse());
    m_Centre = phantom.BlockCentre();
    // The block is the parallelepiped c + sum_k s_k e_k, |s_k| <= h_k, e_k the unit direction columns; s = E^-1 (x - c)
    // takes the rows of E^-1 (the dual basis: E^T when the directions are orthonormal, not when sheared).
    MatrixType unitColumns;
    for (unsigned int a = 0; a < 3; ++a)
    {
      double norm = 0.0;
      for (unsigned int r = 0; r < 3; ++r)
      {
        norm += phantom.direction[r][a] * phantom.direction[r][a];
      }
      for (unsigned int r = 0; r < 3; ++r)
      {
        unitColumns[r][a] = phantom.direction[r][a] / std::sqrt(norm);
      }
    }
    const MatrixType dual(unitColumns.GetInverse());
    for (unsigned int a = 0; a < 3; ++a)
    {
      for (unsigned int r = 0; r < 3; ++r)
      {
        m_Axes[a][r] = dual[a][r];
      }
      m_HalfExtents[a] = 0.5 * phantom.spacing[a] * static_cast<double>(phantom.high[a] - phantom.low[a] + 1);
    }
  }

  /** Line integral of mu over the room segment start -> end. */
  double
  Integrate(KernelEnum kernel, const PointType & start, const PointType & end) const
  {
    const PointType a = this->ToVolume(start);
    const PointType b = this->ToVolume(end);
    const double    roomLength = (end - start).GetNorm();
    const double    parameterIntegral =
      kernel == KernelEnum::Box ? this->BoxParameterIntegral(a, b) : this->TentParameterIntegral(a, b);
    return roomLength * parameterIntegral;
  }

  /** Length (in units of the parameter t in [0, 1]) of the part of a -> b (volume frame) inside the block's box. */
  double
  BoxChordParameter(const PointType & a, const PointType & b) const
  {
    double tEnter = 0.0;
    double tExit = 1.0;
    for (unsigned int k = 0; k < 3; ++k)
    {
      const double o = m_Axes[k] * (a - m_Centre);
      const double d = m_Axes[k] * (b - a);
      const double h = m_HalfExtents[k];
      if (std::abs(d) < 1e-300)
      {
        if (std::abs(o) > h)
        {
          return 0.0;
        }
        continue;
      }
      const double t1 = (-h - o) / d;
      const double t2 = (h - o) / d;
      tEnter = std::max(tEnter, std::min(t1, t2));
      tExit = std::min(tExit, std::max(t1, t2));
    }
    return std::max(0.0, tExit - tEnter);
  }

private:
  PointType
  ToVolume(const PointType & room) const
  {
    return m_Transform ? m_Transform->TransformPoint(room) : room;
  }

  double
  BoxParameterIntegral(const PointType & a, const PointType & b) const
  {
    return m_Phantom.StoredMu() * this->BoxChordParameter(a, b);
  }

  /** 1D trapezoid of the tent model: 1 on [low, high], 0 outside [low - 1, high + 1], linear between. */
  static double
  Trapezoid(double q, double low, double high)
  {
    if (q <= low - 1.0 || q >= high + 1.0)
    {
      return 0.0;
    }
    if (q < low)
    {
      return q - (low - 1.0);
    }
    if (q > high)
    {
      return high + 1.0 - q;
    }
    return 1.0;
  }

  double
  TentParameterIntegral(const PointType & a, const PointType & b) const
  {
    double p0[3];
    double dp[3];
    for (unsigned int r = 0; r < 3; ++r)
    {
      p0[r] = 0.0;
      dp[r] = 0.0;
      for (unsigned int c = 0; c < 3; ++c)
      {
        p0[r] += m_PhysicalToIndex[r][c] * (a[c] - m_Phantom.origin[c]);
        dp[r] += m_PhysicalToIndex[r][c] * (b[c] - a[c]);
      }
    }
    std::vector<double> breaks{ 0.0, 1.0 };
    for (unsigned int k = 0; k < 3; ++k)
    {
      if (dp[k] == 0.0)
      {
        continue;
      }
      const double low = static_cast<double>(m_Phantom.low[k]);
      const double high = static_cast<double>(m_Phantom.high[k]);
      for (double plane : { low - 1.0, low, high, high + 1.0 })
      {
        const double t = (plane - p0[k]) / dp[k];
        if (t > 0.0 && t < 1.0)
        {
          breaks.push_back(t);
        }
      }
    }
    std::sort(breaks.begin(), breaks.end());
    const double nodes[3] = { -std::sqrt(0.6), 0.0, std::sqrt(0.6) };
    const double weights[3] = { 5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0 };
    double       integral = 0.0;
    for (size_t s = 0; s + 1 < breaks.size(); ++s)
    {
      const double half = 0.5 * (breaks[s + 1] - breaks[s]);
      const double middle = 0.5 * (breaks[s + 1] + breaks[s]);
      if (!(half > 0.0))
      {
        continue;
      }
      for (unsigned int g = 0; g < 3; ++g)
      {
        const double t = middle + nodes[g] * half;
        double       value = 1.0;
        for (unsigned int k = 0; k < 3; ++k)
        {
          value *=
            Trapezoid(p0[k] + t * dp[k], static_cast<double>(m_Phantom.low[k]), static_cast<double>(m_Phantom.high[k]));
        }
        integral += weights[g] * half * value;
      }
    }
    return m_Phantom.StoredMu() * integral;
  }

  const BlockPhantom &      m_Phantom;
  const TransformType *     m_Transform;
  MatrixType                m_IndexToPhysical;
  MatrixType                m_PhysicalToIndex;
  PointType                 m_Centre;
  std::array<VectorType, 3> m_Axes;
  std::array<double, 3>     m_HalfExtents;
};

/** The room segment of the ray through detector point (column, row), fractional allowed. */
std::pair<PointType, PointType>
RaySegment(const GeometryType * geometry, double column, double row)
{
  const PointType pixel = geometry->GetPixelCenter(column, row);
  if (geometry->GetProjection() == ProjectionEnum::Perspective)
  {
    return { geometry->GetSourcePosition(), pixel };
  }
  if (geometry->GetProjection() == ProjectionEnum::Localizer)
  {
    // The table has carried the source along the rows to this row: its detector coordinate along v, from the foot of
    // the normal, is offset_v + (row - (rows - 1) / 2) dv.
    const double along = geometry->GetDetectorOffset()[1] +
                         (row - 0.5 * (geometry->GetDetectorSize()[1] - 1.0)) * geometry->GetDetectorSpacing()[1];
    return { geometry->GetSourcePosition() + geometry->GetRowDirection() * along, pixel };
  }
  const VectorType n = geometry->GetNormal();
  return { pixel + n * kParallelHalfLength, pixel - n * kParallelHalfLength };
}

/** Closed-form image (columns fastest): each pixel the average of k x k rays at the centres of a k x k split. */
std::vector<double>
ReferenceImage(const BlockPhantom &  phantom,
               const GeometryType *  geometry,
               KernelEnum            kernel,
               unsigned int          raysPerSide = 1,
               const TransformType * transform = nullptr)
{
  const ClosedFormReference reference(phantom, transform);
  const unsigned int        columns = geometry->GetDetectorSize()[0];
  const unsigned int        rows = geometry->GetDetectorSize()[1];
  std::vector<double>       image(static_cast<size_t>(columns) * rows, 0.0);
  for (unsigned int j = 0; j < rows; ++j)
  {
    for (unsigned int i = 0; i < columns; ++i)
    {
      double sum = 0.0;
      for (unsigned int l = 0; l < raysPerSide; ++l)
      {
        const double row = j + (l + 0.5) / raysPerSide - 0.5;
        for (unsigned int m = 0; m < raysPerSide; ++m)
        {
          const double column = i + (m + 0.5) / raysPerSide - 0.5;
          const auto   segment = RaySegment(geometry, column, row);
          sum += reference.Integrate(kernel, segment.first, segment.second);
        }
      }
      image[static_cast<size_t>(j) * columns + i] = sum / (raysPerSide * raysPerSide);
    }
  }
  return image;
}

template <typename TOutput = OutputImageType>
typename itk::ExactDRRImageFilter<MuVolumeType, TOutput>::Pointer
MakeFilter(const MuVolumeType *  volume,
           GeometryType *        geometry,
           KernelEnum            kernel,
           unsigned int          raysPerSide = 1,
           const TransformType * transform = nullptr)
{
  auto filter = itk::ExactDRRImageFilter<MuVolumeType, TOutput>::New();
  filter->SetInput(volume);
  filter->SetGeometry(geometry);
  filter->GetTransferFunction()->SetMode(TransferEnum::Identity);
  filter->SetReconstructionKernel(kernel);
  filter->SetRaysPerPixelSide(raysPerSide);
  if (transform)
  {
    filter->SetTransform(transform);
  }
  return filter;
}

std::vector<double>
Render(const MuVolumeType *  volume,
       GeometryType *        geometry,
       KernelEnum            kernel,
       unsigned int          raysPerSide = 1,
       const TransformType * transform = nullptr)
{
  auto filter = MakeFilter(volume, geometry, kernel, raysPerSide, transform);
  filter->Update();
  const OutputImageType * output = filter->GetOutput();
  EXPECT_EQ(output->GetLargestPossibleRegion().GetSize()[0], geometry->GetDetectorSize()[0]);
  EXPECT_EQ(output->GetLargestPossibleRegion().GetSize()[1], geometry->GetDetectorSize()[1]);
  return PointBasedDRRTest::ToVector(output);
}

struct ComparisonStatistics
{
  double       maximumRelativeError{ 0.0 };
  unsigned int hits{ 0 };   // pixels with a non-negligible reference
  unsigned int misses{ 0 }; // pixels whose reference is ~0
};

/** Every pixel against the reference: relative error < 1e-6, or absolute 1e-9 where the reference is ~0. */
ComparisonStatistics
CompareImages(const std::vector<double> & image,
              const std::vector<double> & reference,
              unsigned int                columns,
              const std::string &         label)
{
  ComparisonStatistics statistics;
  EXPECT_EQ(image.size(), reference.size()) << label;
  for (size_t p = 0; p < std::min(image.size(), reference.size()); ++p)
  {
    const double expected = reference[p];
    const double actual = image[p];
    EXPECT_TRUE(std::isfinite(actual)) << label << " pixel (" << p % columns << ", " << p / columns << ")";
    const double tolerance = std::max(kRelativeTolerance * std::abs(expected), kAbsoluteTolerance);
    EXPECT_NEAR(actual, expected, tolerance) << label << " pixel (" << p % columns << ", " << p / columns << ")";
    if (std::abs(expected) > kAbsoluteTolerance)
    {
      ++statistics.hits;
      statistics.maximumRelativeError =
        std::max(statistics.maximumRelativeError, std::abs(actual - expected) / std::abs(expected));
    }
    else
    {
      ++statistics.misses;
    }
  }
  return statistics;
}

/** Renders with the filter and compares every pixel to the closed form; returns the statistics. */
ComparisonStatistics
CheckScene(const BlockPhantom &  phantom,
           GeometryType *        geometry,
           KernelEnum            kernel,
           const std::string &   label,
           unsigned int          raysPerSide = 1,
           const TransformType * transform = nullptr)
{
  const auto volume = phantom.MakeVolume();
  const auto image = Render(volume, geometry, kernel, raysPerSide, transform);
  const auto reference = ReferenceImage(phantom, geometry, kernel, raysPerSide, transform);
  const auto statistics = CompareImages(image, reference, geometry->GetDetectorSize()[0], label);
  EXPECT_GT(statistics.hits, 0u) << label << ": no ray hits the block, the test would prove nothing";
  return statistics;
}

double
MaximumAbsoluteDifference(const std::vector<double> & a, const std::vector<double> & b)
{
  double difference = 0.0;
  for (size_t p = 0; p < std::min(a.size(), b.size()); ++p)
  {
    difference = std::max(difference, std::abs(a[p] - b[p]));
  }
  return difference;
}

double
MaximumValue(const std::vector<double> & a)
{
  return *std::max_element(a.begin(), a.end());
}

GeometryType::Pointer
MakeGeometry(ProjectionEnum    projection,
             double            sad,
             double            sid,
             const PointType & isocenter,
             unsigned int      columns = 9,
             unsigned int      rows = 7,
             double            du = 3.5,
             double            dv = 4.0)
{
  auto geometry = GeometryType::New();
  geometry->SetProjection(projection);
  geometry->SetSourceToIsocenterDistance(sad);
  geometry->SetSourceToDetectorDistance(sid);
  geometry->SetIsocenter(isocenter);
  GeometryType::DetectorSizeType size;
  size[0] = columns;
  size[1] = rows;
  geometry->SetDetectorSize(size);
  GeometryType::DetectorVectorType spacing;
  spacing[0] = du;
  spacing[1] = dv;
  geometry->SetDetectorSpacing(spacing);
  geometry->SetGantryAngleInDegrees(0.0);
  return geometry;
}

/** Prints and returns the running maximum relative error of a test. */
void
Report(const std::string & test, double maximumRelativeError)
{
  std::cout << "[ max rel ] " << test << ": " << maximumRelativeError << std::endl;
  ::testing::Test::RecordProperty("MaximumRelativeError", std::to_string(maximumRelativeError));
}

/** 6 x 5 x 4 voxels of 1.5 x 2 x 3 mm, all 0.02 /mm, centred at the origin. */
BlockPhantom
FullBoxPhantom()
{
  BlockPhantom phantom;
  phantom.size = { { 6, 5, 4 } };
  phantom.spacing[0] = 1.5;
  phantom.spacing[1] = 2.0;
  phantom.spacing[2] = 3.0;
  phantom.low = { { 0, 0, 0 } };
  phantom.high = { { 5, 4, 3 } };
  phantom.mu = 0.02;
  CentreVolumeAt(phantom, PointType(0.0));
  return phantom;
}

/** A 4 x 3 x 5 sub-block of 0.015 /mm inside a 10 x 9 x 8 zero volume, off the volume's centre. */
BlockPhantom
OffCentreBlockPhantom()
{
  BlockPhantom phantom;
  phantom.size = { { 10, 9, 8 } };
  phantom.spacing[0] = 1.2;
  phantom.spacing[1] = 0.9;
  phantom.spacing[2] = 1.6;
  phantom.origin[0] = -5.3;
  phantom.origin[1] = -3.1;
  phantom.origin[2] = -6.2;
  phantom.low = { { 2, 5, 1 } };
  phantom.high = { { 5, 7, 5 } };
  phantom.mu = 0.015;
  return phantom;
}
} // namespace

// 1. A volume filled to its faces, anisotropic spacing, identity direction.
TEST(ExactDRRImageFilter, FullBoxAnisotropicSpacing)
{
  const BlockPhantom phantom = FullBoxPhantom();
  double             worst = 0.0;
  for (const auto projection : kProjections)
  {
    auto geometry = MakeGeometry(projection, 100.0, 160.0, PointType(0.0));
    for (const auto kernel : kKernels)
    {
      const std::string label = "full box, " + Name(projection) + ", " + Name(kernel);
      const auto        statistics = CheckScene(phantom, geometry, kernel, label);
      EXPECT_GT(statistics.misses, 0u) << label << ": the detector should extend past the volume's shadow";
      worst = std::max(worst, statistics.maximumRelativeError);

      // The central ray runs along x through the isocentre: 6 voxels of 1.5 mm at 0.02 /mm. For the tent model the
      // profile along x is a trapezoid of the same area, and T_y = T_z = 1 there.
      const auto image = Render(phantom.MakeVolume(), geometry, kernel);
      EXPECT_NEAR(image[3 * 9 + 4], 9.0 * phantom.StoredMu(), 1e-12) << label;
    }
  }
  Report("FullBoxAnisotropicSpacing", worst);
}

// 2. A sub-block inside a larger zero volume, perspective and parallel.
TEST(ExactDRRImageFilter, OffCentreBlock)
{
  const BlockPhantom phantom = OffCentreBlockPhantom();
  double             worst = 0.0;
  for (const auto projection : kProjections)
  {
    auto geometry = MakeGeometry(projection, 100.0, 160.0, PointType(0.0), 9, 7, 2.0, 2.5);
    for (const auto kernel : kKernels)
    {
      const std::string label = "off-centre block, " + Name(projection) + ", " + Name(kernel);
      const auto        statistics = CheckScene(phantom, geometry, kernel, label);
      EXPECT_GT(statistics.misses, 0u) << label;
      worst = std::max(worst, statistics.maximumRelativeError);
    }
  }
  Report("OffCentreBlock", worst);
}

// 3. The direction matrix is honoured: rotated, permuted with det -1 and det +1, and sheared (a gantry-tilted series,
// non-orthogonal), with a nonzero origin.
TEST(ExactDRRImageFilter, DirectionMatrixHonoured)
{
  VectorType axis;
  axis[0] = 1.0;
  axis[1] = 2.0;
  axis[2] = 3.0;
  axis /= axis.GetNorm();
  MatrixType swapXY; // det -1
  swapXY.Fill(0.0);
  swapXY[0][1] = 1.0;
  swapXY[1][0] = 1.0;
  swapXY[2][2] = 1.0;
  MatrixType cyclic; // det +1
  cyclic.Fill(0.0);
  cyclic[0][2] = 1.0;
  cyclic[1][0] = 1.0;
  cyclic[2][1] = 1.0;
  // A gantry tilt: the image plane tilted by 18.5 degrees about x, the slices stepping along z (as a Philips series
  // tilted -18.5 degrees reads): a sheared, non-orthogonal direction matrix. Then the same, rotated.
  const double tilt = 18.5 * itk::Math::pi / 180.0;
  MatrixType   sheared;
  sheared.SetIdentity();
  sheared[1][1] = std::cos(tilt);
  sheared[2][1] = -std::sin(tilt);
  const std::vector<std::pair<std::string, MatrixType>> directions{
    { "rotated 30 deg about (1,2,3)", PointBasedDRRTest::RotationMatrix(axis, 30.0) },
    { "permuted det -1", swapXY },
    { "permuted det +1", cyclic },
    { "sheared: gantry tilt 18.5 deg", sheared },
    { "sheared and rotated", PointBasedDRRTest::RotationMatrix(axis, 30.0) * sheared },
  };

  double worst = 0.0;
  for (const auto & direction : directions)
  {
    BlockPhantom phantom;
    phantom.size = { { 7, 6, 5 } };
    phantom.spacing[0] = 1.1;
    phantom.spacing[1] = 1.7;
    phantom.spacing[2] = 2.3;
    phantom.origin[0] = 3.1;
    phantom.origin[1] = -2.7;
    phantom.origin[2] = 1.9;
    phantom.direction = direction.second;
    phantom.low = { { 1, 2, 0 } };
    phantom.high = { { 4, 4, 3 } };
    phantom.mu = 0.02;
    // Aim at the block's centre (slightly off, so that no ray sits on a symmetry plane).
    PointType isocenter = phantom.BlockCentre();
    isocenter[0] += 0.37;
    isocenter[1] -= 0.21;
    isocenter[2] += 0.13;

    BlockPhantom identityPhantom = phantom;
    identityPhantom.direction.SetIdentity();

    for (const auto projection : kProjections)
    {
      auto geometry = MakeGeometry(projection, 100.0, 160.0, isocenter, 9, 7, 2.5, 3.0);
      for (const auto kernel : kKernels)
      {
        const std::string label = direction.first + ", " + Name(projection) + ", " + Name(kernel);
        const auto        statistics = CheckScene(phantom, geometry, kernel, label);
        worst = std::max(worst, statistics.maximumRelativeError);

        // Sensitivity: a projector that ignored the direction would render this instead, far from the truth.
        const auto truth = ReferenceImage(phantom, geometry, kernel);
        const auto ignoringDirection = ReferenceImage(identityPhantom, geometry, kernel);
        EXPECT_GT(MaximumAbsoluteDifference(truth, ignoringDirection), 0.1 * MaximumValue(truth)) << label;
      }
    }
  }
  Report("DirectionMatrixHonoured", worst);
}

// 4. Gantry angles 0, 90, 30 and an oblique normal.
TEST(ExactDRRImageFilter, GantryAnglesAndObliqueNormal)
{
  BlockPhantom phantom = OffCentreBlockPhantom();
  phantom.direction = PointBasedDRRTest::RotationMatrix(VectorType(std::sqrt(1.0 / 3.0)), 17.0);
  const PointType isocenter = phantom.BlockCentre() + VectorType(0.23);

  double worst = 0.0;
  for (const auto projection : kProjections)
  {
    std::vector<std::pair<std::string, GeometryType::Pointer>> geometries;
    for (const double angle : { 0.0, 90.0, 30.0 })
    {
      auto geometry = MakeGeometry(projection, 100.0, 160.0, isocenter, 9, 7, 2.0, 2.5);
      geometry->SetGantryAngleInDegrees(angle);
      geometries.emplace_back("gantry " + std::to_string(angle), geometry);
    }
    auto       oblique = MakeGeometry(projection, 100.0, 160.0, isocenter, 9, 7, 2.0, 2.5);
    VectorType normal;
    normal[0] = 1.0;
    normal[1] = -2.0;
    normal[2] = 0.7;
    oblique->SetNormal(normal);
    geometries.emplace_back("oblique normal (1,-2,0.7)", oblique);

    std::vector<std::vector<double>> images;
    for (const auto & geometry : geometries)
    {
      for (const auto kernel : kKernels)
      {
        const std::string label = geometry.first + ", " + Name(projection) + ", " + Name(kernel);
        const auto        statistics = CheckScene(phantom, geometry.second, kernel, label);
        worst = std::max(worst, statistics.maximumRelativeError);
        if (kernel == KernelEnum::Box)
        {
          images.push_back(Render(phantom.MakeVolume(), geometry.second, kernel));
        }
      }
    }
    // The views differ from each other (the angle is not ignored).
    for (size_t a = 0; a < images.size(); ++a)
    {
      for (size_t b = a + 1; b < images.size(); ++b)
      {
        EXPECT_GT(MaximumAbsoluteDifference(images[a], images[b]), 1e-3)
          << geometries[a].first << " vs " << geometries[b].first << ", " << Name(projection);
      }
    }
  }
  Report("GantryAnglesAndObliqueNormal", worst);
}

// 5. A linear transform (room -> volume frame): rigid Euler3D and an anisotropic scaling affine.
TEST(ExactDRRImageFilter, LinearTransform)
{
  const BlockPhantom phantom = OffCentreBlockPhantom();
  const PointType    centre = phantom.BlockCentre();

  auto rigid = itk::Euler3DTransform<double>::New();
  rigid->SetCenter(centre);
  rigid->SetRotation(0.3, -0.2, 0.5);
  itk::Euler3DTransform<double>::OutputVectorType translation;
  translation[0] = 2.5;
  translation[1] = -1.5;
  translation[2] = 1.0;
  rigid->SetTranslation(translation);

  auto       affine = itk::AffineTransform<double, 3>::New();
  VectorType axis;
  axis[0] = -0.4;
  axis[1] = 0.8;
  axis[2] = 0.3;
  axis /= axis.GetNorm();
  MatrixType scaling;
  scaling.Fill(0.0);
  scaling[0][0] = 1.3;
  scaling[1][1] = 0.8;
  scaling[2][2] = 1.15;
  affine->SetCenter(centre);
  affine->SetMatrix(PointBasedDRRTest::RotationMatrix(axis, 20.0) * scaling);
  itk::AffineTransform<double, 3>::OutputVectorType affineTranslation;
  affineTranslation[0] = -1.0;
  affineTranslation[1] = 0.7;
  affineTranslation[2] = 1.4;
  affine->SetTranslation(affineTranslation);

  const std::vector<std::pair<std::string, const TransformType *>> transforms{
    { "rigid Euler3D", rigid.GetPointer() },
    { "anisotropic scaling affine", affine.GetPointer() },
  };

  double worst = 0.0;
  for (const auto & transform : transforms)
  {
    for (const auto projection : kProjections)
    {
      auto geometry = MakeGeometry(projection, 100.0, 160.0, centre, 9, 7, 2.5, 3.0);
      geometry->SetGantryAngleInDegrees(25.0);
      for (const auto kernel : kKernels)
      {
        const std::string label = transform.first + ", " + Name(projection) + ", " + Name(kernel);
        const auto        statistics = CheckScene(phantom, geometry, kernel, label, 1, transform.second);
        worst = std::max(worst, statistics.maximumRelativeError);

        // Sensitivity: the transform changes the image.
        const auto moved = ReferenceImage(phantom, geometry, kernel, 1, transform.second);
        const auto unmoved = ReferenceImage(phantom, geometry, kernel);
        EXPECT_GT(MaximumAbsoluteDifference(moved, unmoved), 0.05 * MaximumValue(moved)) << label;
      }
    }
  }

  // For the scaling, the room length of a chord is not its volume-frame length: check one ray by hand. A parallel ray
  // along x through the block centre (no rotation here): the volume frame sees the room x axis stretched by 1.3, so
  // the block's x extent (4 voxels of 1.2 mm) spans 4.8 / 1.3 mm of the room.
  auto stretch = itk::AffineTransform<double, 3>::New();
  stretch->SetCenter(centre);
  stretch->SetMatrix(scaling);
  auto       geometry = MakeGeometry(ProjectionEnum::Parallel, 100.0, 160.0, centre, 3, 3, 0.1, 0.1);
  const auto image = Render(phantom.MakeVolume(), geometry, KernelEnum::Box, 1, stretch);
  EXPECT_NEAR(image[4], phantom.StoredMu() * 4.8 / 1.3, 1e-12);
  Report("LinearTransform", worst);
}

// 6. Supersampling: k x k rays per pixel at offsets ((m + 0.5) / k - 0.5) pixels.
TEST(ExactDRRImageFilter, SupersamplingThreeByThree)
{
  const BlockPhantom phantom = OffCentreBlockPhantom();
  double             worst = 0.0;
  for (const auto projection : kProjections)
  {
    auto geometry = MakeGeometry(projection, 100.0, 160.0, PointType(0.0), 9, 7, 2.0, 2.5);
    geometry->SetGantryAngleInDegrees(30.0);
    for (const auto kernel : kKernels)
    {
      const std::string label = "k = 3, " + Name(projection) + ", " + Name(kernel);
      const auto        statistics = CheckScene(phantom, geometry, kernel, label, 3);
      worst = std::max(worst, statistics.maximumRelativeError);
      // Sensitivity: the average of 9 rays differs from the central ray at the block's edges.
      EXPECT_GT(MaximumAbsoluteDifference(ReferenceImage(phantom, geometry, kernel, 3),
                                          ReferenceImage(phantom, geometry, kernel, 1)),
                1e-3)
        << label;
    }
  }
  Report("SupersamplingThreeByThree", worst);
}

// 7. Source inside the volume, and detector plane cutting through it: only the source -> pixel segment counts.
TEST(ExactDRRImageFilter, SourceOrDetectorInsideVolume)
{
  BlockPhantom phantom;
  phantom.size = { { 8, 8, 8 } };
  phantom.spacing.Fill(2.5);
  phantom.low = { { 0, 0, 0 } };
  phantom.high = { { 7, 7, 7 } };
  phantom.mu = 0.02;
  PointType centre;
  centre[0] = 0.31;
  centre[1] = -0.17;
  centre[2] = 0.11;
  CentreVolumeAt(phantom, centre);

  double worst = 0.0;
  // Source at x = 4 inside the box [-9.69, 10.31] (x); detector plane at x = -26 outside.
  // Then source outside, detector plane at x = -5 inside the box.
  const std::vector<std::pair<double, double>> sadSid{ { 4.0, 30.0 }, { 30.0, 35.0 } };
  for (const auto & distances : sadSid)
  {
    auto geometry =
      MakeGeometry(ProjectionEnum::Perspective, distances.first, distances.second, PointType(0.0), 9, 7, 4.0, 5.0);
    for (const auto kernel : kKernels)
    {
      const std::string label =
        "SAD " + std::to_string(distances.first) + ", SID " + std::to_string(distances.second) + ", " + Name(kernel);
      const auto statistics = CheckScene(phantom, geometry, kernel, label);
      worst = std::max(worst, statistics.maximumRelativeError);
    }
    // The central ray along -x: box model chord from the source (or the box entry) to the pixel (or the box exit).
    const double sourceX = distances.first;
    const double pixelX = distances.first - distances.second;
    const double boxLow = centre[0] - 10.0;
    const double boxHigh = centre[0] + 10.0;
    const double chord = std::min(sourceX, boxHigh) - std::max(pixelX, boxLow);
    const auto   image = Render(phantom.MakeVolume(), geometry, KernelEnum::Box);
    EXPECT_NEAR(image[3 * 9 + 4], phantom.StoredMu() * chord, 1e-12);
  }
  Report("SourceOrDetectorInsideVolume", worst);
}

// 8. The outer half-voxel shell is kept: one 2 mm voxel; and an all-zero volume is exactly zero.
TEST(ExactDRRImageFilter, SingleVoxelAndZeroVolume)
{
  BlockPhantom phantom;
  phantom.size = { { 1, 1, 1 } };
  phantom.spacing.Fill(2.0);
  phantom.low = { { 0, 0, 0 } };
  phantom.high = { { 0, 0, 0 } };
  phantom.mu = 0.01;
  CentreVolumeAt(phantom, PointType(0.0));

  double worst = 0.0;
  for (const auto projection : kProjections)
  {
    auto geometry = MakeGeometry(projection, 100.0, 160.0, PointType(0.0), 7, 5, 1.2, 1.3);
    for (const auto kernel : kKernels)
    {
      const std::string label = "single voxel, " + Name(projection) + ", " + Name(kernel);
      const auto        statistics = CheckScene(phantom, geometry, kernel, label);
      EXPECT_GT(statistics.misses, 0u) << label;
      worst = std::max(worst, statistics.maximumRelativeError);
      if (projection == ProjectionEnum::Parallel)
      {
        // Box: 2 mm chord; tent: a tent of half-width 2 mm and height 1 (T_y T_z = 1 at the centre): area 2 mm.
        const auto image = Render(phantom.MakeVolume(), geometry, kernel);
        EXPECT_NEAR(image[2 * 7 + 3], 0.02, 1e-9) << label;
      }
    }
  }

  BlockPhantom zero = FullBoxPhantom();
  zero.mu = 0.0;
  for (const auto projection : kProjections)
  {
    auto geometry = MakeGeometry(projection, 100.0, 160.0, PointType(0.0));
    for (const auto kernel : kKernels)
    {
      for (const double value : Render(zero.MakeVolume(), geometry, kernel, 2))
      {
        EXPECT_EQ(value, 0.0) << "all-zero volume, " << Name(projection) << ", " << Name(kernel);
      }
    }
  }
  Report("SingleVoxelAndZeroVolume", worst);
}

// 9. Output modes: transmission, 8- and 16-bit windowed gray levels, and an integer output refused for line integrals.
TEST(ExactDRRImageFilter, OutputModes)
{
  const BlockPhantom phantom = OffCentreBlockPhantom();
  const auto         volume = phantom.MakeVolume();
  // Tent model and an oblique view: a graded image, so that a window has pixels below, inside and above it.
  const KernelEnum kernel = KernelEnum::Tent;
  auto             geometry = MakeGeometry(ProjectionEnum::Perspective, 100.0, 160.0, PointType(0.0), 9, 7, 2.0, 2.5);
  geometry->SetGantryAngleInDegrees(30.0);
  const auto reference = ReferenceImage(phantom, geometry, kernel);
  const auto lineIntegral = Render(volume, geometry, kernel);
  CompareImages(lineIntegral, reference, 9, "line integral for the output modes");
  const double maximum = MaximumValue(lineIntegral);
  ASSERT_GT(maximum, 0.05);

  // Transmission exp(-L), in double and in float.
  {
    auto filter = MakeFilter(volume, geometry, kernel);
    filter->SetOutputMode(OutputModeEnum::Transmission);
    filter->Update();
    const auto transmission = PointBasedDRRTest::ToVector(filter->GetOutput());
    double     worst = 0.0;
    for (size_t p = 0; p < reference.size(); ++p)
    {
      const double expected = std::exp(-reference[p]);
      EXPECT_NEAR(transmission[p], expected, kRelativeTolerance * expected) << "transmission pixel " << p;
      worst = std::max(worst, std::abs(transmission[p] - expected) / expected);
    }
    Report("OutputModes (transmission)", worst);

    auto floatFilter = MakeFilter<PointBasedDRRTest::ProjectionType>(volume, geometry, kernel);
    floatFilter->SetOutputMode(OutputModeEnum::Transmission);
    floatFilter->Update();
    const auto floatTransmission = PointBasedDRRTest::ToVector(floatFilter->GetOutput());
    for (size_t p = 0; p < reference.size(); ++p)
    {
      EXPECT_NEAR(floatTransmission[p], std::exp(-reference[p]), 1e-6) << "float transmission pixel " << p;
    }
  }

  // Gray levels: round(clamp((L - (level - width / 2)) / width, 0, 1) * max), with a window that clips both ends.
  const double level = 0.45 * maximum;
  const double width = 0.6 * maximum;
  auto         expectedGray = [&](double value, double low, double w, double grayMaximum) {
    return std::floor(std::min(1.0, std::max(0.0, (value - low) / w)) * grayMaximum + 0.5);
  };
  {
    using Gray8Type = itk::Image<unsigned char, 2>;
    auto filter = MakeFilter<Gray8Type>(volume, geometry, kernel);
    filter->SetOutputMode(OutputModeEnum::Gray8);
    filter->SetWindowLevel(level);
    filter->SetWindowWidth(width);
    filter->Update();
    const auto   gray = PointBasedDRRTest::ToVector(filter->GetOutput());
    unsigned int black = 0;
    unsigned int white = 0;
    unsigned int between = 0;
    for (size_t p = 0; p < gray.size(); ++p)
    {
      EXPECT_EQ(gray[p], expectedGray(lineIntegral[p], level - 0.5 * width, width, 255.0)) << "gray8 pixel " << p;
      // Against the closed form, up to one gray level where L sits on a rounding boundary.
      EXPECT_NEAR(gray[p], expectedGray(reference[p], level - 0.5 * width, width, 255.0), 1.0) << "gray8 pixel " << p;
      black += gray[p] == 0.0;
      white += gray[p] == 255.0;
      between += gray[p] > 0.0 && gray[p] < 255.0;
    }
    EXPECT_GT(black, 0u);
    EXPECT_GT(white, 0u);
    EXPECT_GT(between, 0u);

    // Width 0: the automatic window, the image's 0.5th to 99.5th percentile (sorted values at floor(q (n - 1))), so
    // that the extremes map to 0 and 255 and a few outliers cannot take the gray levels.
    auto automatic = MakeFilter<Gray8Type>(volume, geometry, kernel);
    automatic->SetOutputMode(OutputModeEnum::Gray8);
    automatic->Update();
    const auto          autoGray = PointBasedDRRTest::ToVector(automatic->GetOutput());
    std::vector<double> sorted(lineIntegral.begin(), lineIntegral.end());
    std::sort(sorted.begin(), sorted.end());
    const double low = sorted[static_cast<size_t>(0.005 * static_cast<double>(sorted.size() - 1))];
    const double high = sorted[static_cast<size_t>(0.995 * static_cast<double>(sorted.size() - 1))];
    ASSERT_GT(high, low);
    for (size_t p = 0; p < autoGray.size(); ++p)
    {
      EXPECT_EQ(autoGray[p], expectedGray(lineIntegral[p], low, high - low, 255.0)) << "auto gray8 " << p;
    }
    EXPECT_EQ(*std::max_element(autoGray.begin(), autoGray.end()), 255.0);
    EXPECT_EQ(*std::min_element(autoGray.begin(), autoGray.end()), 0.0);
  }
  {
    using Gray16Type = itk::Image<unsigned short, 2>;
    auto filter = MakeFilter<Gray16Type>(volume, geometry, kernel);
    filter->SetOutputMode(OutputModeEnum::Gray16);
    filter->SetWindowLevel(level);
    filter->SetWindowWidth(width);
    filter->Update();
    const auto gray = PointBasedDRRTest::ToVector(filter->GetOutput());
    for (size_t p = 0; p < gray.size(); ++p)
    {
      EXPECT_EQ(gray[p], expectedGray(lineIntegral[p], level - 0.5 * width, width, 65535.0)) << "gray16 pixel " << p;
    }
  }

  // An integer output cannot hold line integrals (nor transmissions): refused by VerifyPreconditions(), before the
  // render starts (no StartEvent).
  {
    using Gray8Type = itk::Image<unsigned char, 2>;
    auto         filter = MakeFilter<Gray8Type>(volume, geometry, kernel);
    unsigned int starts = 0;
    auto         counter = itk::CStyleCommand::New();
    counter->SetClientData(&starts);
    counter->SetCallback(
      [](itk::Object *, const itk::EventObject &, void * count) { ++*static_cast<unsigned int *>(count); });
    filter->AddObserver(itk::StartEvent(), counter);
    EXPECT_TRUE(PointBasedDRRTest::Contains(
      PointBasedDRRTest::ExceptionMessage([&] { filter->Update(); }, "gray8 line"), "holds only the Gray8 or Gray16"));
    EXPECT_EQ(starts, 0u);
    auto transmission = MakeFilter<Gray8Type>(volume, geometry, kernel);
    transmission->SetOutputMode(OutputModeEnum::Transmission);
    EXPECT_THROW(transmission->Update(), itk::ExceptionObject);
  }
}

// A localizer's rows are parallel and its columns a fan: a block's shadow is magnified SID / depth across the columns
// and not at all along the rows (closed form above, and here its extent).
TEST(ExactDRRImageFilter, LocalizerMagnifiesColumnsOnly)
{
  BlockPhantom phantom = FullBoxPhantom(); // 9 x 10 x 12 mm
  auto         geometry = MakeGeometry(ProjectionEnum::Localizer, 100.0, 200.0, PointType(0.0), 61, 41, 0.5, 0.5);
  const auto   image = Render(phantom.MakeVolume(), geometry, KernelEnum::Box);
  // Shadow width in pixels along columns (y, 10 mm) and rows (z, 12 mm): magnified by 200 / 100 across, 1 along.
  unsigned int columnsHit = 0, rowsHit = 0;
  for (unsigned int i = 0; i < 61; ++i)
  {
    columnsHit += image[20 * 61 + i] > 0.0 ? 1 : 0;
  }
  for (unsigned int j = 0; j < 41; ++j)
  {
    rowsHit += image[j * 61 + 30] > 0.0 ? 1 : 0;
  }
  // The central face at depth 100 - 4.5 .. 100 + 4.5: the near face's 10 mm casts 10 * 200 / 95.5 = 20.9 mm.
  EXPECT_NEAR(columnsHit * 0.5, 10.0 * 200.0 / 95.5, 1.0);
  EXPECT_NEAR(rowsHit * 0.5, 12.0, 1.0);
  const auto statistics = CheckScene(phantom, geometry, KernelEnum::Box, "localizer block", 2);
  EXPECT_GT(statistics.misses, 0u);
}

// Mirrored columns render the mirror image of the plain view whose offset along the columns is the opposite.
TEST(ExactDRRImageFilter, MirroredColumnsRenderTheFlippedImage)
{
  const BlockPhantom phantom = OffCentreBlockPhantom();
  const auto         volume = phantom.MakeVolume();
  for (const auto projection : kProjections)
  {
    auto plain = MakeGeometry(projection, 100.0, 160.0, PointType(0.0), 9, 7, 2.0, 2.5);
    plain->SetGantryAngleInDegrees(25.0);
    auto mirrored = MakeGeometry(projection, 100.0, 160.0, PointType(0.0), 9, 7, 2.0, 2.5);
    mirrored->SetGantryAngleInDegrees(25.0);
    mirrored->SetColumnsMirrored(true);
    GeometryType::DetectorVectorType offset;
    offset[0] = 1.7;
    offset[1] = -0.9;
    mirrored->SetDetectorOffset(offset);
    offset[0] = -offset[0];
    plain->SetDetectorOffset(offset);
    const auto a = Render(volume, plain, KernelEnum::Box);
    const auto b = Render(volume, mirrored, KernelEnum::Box);
    double     peak = 0.0;
    for (unsigned int j = 0; j < 7; ++j)
    {
      for (unsigned int i = 0; i < 9; ++i)
      {
        EXPECT_NEAR(b[j * 9 + i], a[j * 9 + (8 - i)], 1e-12) << Name(projection) << " pixel " << i << ", " << j;
        peak = std::max(peak, a[j * 9 + i]);
      }
    }
    EXPECT_GT(peak, 0.0);
    // And it is not symmetric by itself: the test would see a mirror that changed nothing.
    EXPECT_GT(MaximumAbsoluteDifference(a, b), 0.1 * peak) << Name(projection);
  }
}
