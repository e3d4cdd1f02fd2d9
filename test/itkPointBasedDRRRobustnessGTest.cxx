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
// Robustness of the DRR filters (bad input is rejected with an exception that names the problem) and the numerical
// extremes of docs/design.md section 8 (all air, one voxel, one sample, HU limits, anisotropic, left-handed voxels, the
// source next to or inside the volume, the detector cutting the volume, rays far off-axis, beams along a voxel axis,
// transforms at the edge, float HU beyond any scanner's range, 2^33 samples), plus progress, abort, caching and
// reproducibility under a transform.
//
// Wherever a value is checked against the exact projector, the check is a z-test: the mean over seeds of the
// point-based estimate against the exact filter's pixel average of k x k rays, with the standard error of the mean
// taken from the observed spread over seeds and the reference's own discretization error (the change from k / 2 to k
// rays per pixel side) in the denominator.

#include "itkDRRCompatibility.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkDRRSamplerFactory.h"
#include "itkAffineTransform.h"
#include "itkBSplineTransform.h"
#include "itkEuler3DTransform.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkOutputWindow.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "vnl/vnl_det.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <unistd.h>
#include <functional>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

namespace
{
using namespace PointBasedDRRTest;
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
using SplatEnum = itk::PointBasedDRREnums::Splat;
using ProjectionEnum = itk::PointBasedDRREnums::Projection;
using OutputModeEnum = itk::PointBasedDRREnums::OutputMode;
using TransferEnum = itk::PointBasedDRREnums::TransferFunction;
using GeometryType = itk::DRRProjectionGeometry;
using GrayProjectionType = itk::Image<unsigned char, 2>;

template <typename TVolume, typename TOutput = ProjectionType>
using PointBasedFilter = itk::PointBasedDRRImageFilter<TVolume, TOutput>;
template <typename TVolume, typename TOutput = ProjectionType>
using ExactFilter = itk::ExactDRRImageFilter<TVolume, TOutput>;
template <typename TVolume>
using FilterBase = itk::DRRImageFilterBase<TVolume, ProjectionType>;
template <typename TVolume>
using Configure = std::function<void(FilterBase<TVolume> *)>;

/** Bound on |z|: with 32 seeds the mean is t-distributed with 31 degrees of freedom, P(|t| > 5) is about 2e-5. */
constexpr double zBound = 5.0;
/** mu of water at the default 60 keV (1/mm). */
constexpr double muWater = 0.02059;

double
MuOfHU(double hu)
{
  return hu <= -1000.0 ? 0.0 : static_cast<double>(static_cast<float>(muWater * (1.0 + hu / 1000.0)));
}

std::string
Lower(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

/** Update() must throw an ExceptionObject whose description contains every keyword (case-insensitive). */
template <typename TFilter>
void
ExpectUpdateThrows(TFilter * filter, const std::vector<std::string> & keywords, const std::string & context)
{
  bool thrown = false;
  try
  {
    filter->Update();
  }
  catch (const itk::ExceptionObject & e)
  {
    thrown = true;
    const std::string description = Lower(e.GetDescription());
    for (const auto & keyword : keywords)
    {
      EXPECT_NE(description.find(Lower(keyword)), std::string::npos)
        << context << ": the message does not mention \"" << keyword << "\": " << e.GetDescription();
    }
  }
  EXPECT_TRUE(thrown) << context << ": Update() did not throw";
}

/** A zero-filled volume of the given size and spacing, centred on the room origin. */
template <typename TVolume>
typename TVolume::Pointer
MakeCentredVolume(const typename TVolume::SizeType &      size,
                  const itk::Vector<double, 3> &          spacing,
                  const typename TVolume::DirectionType & direction)
{
  typename TVolume::SpacingType s;
  typename TVolume::PointType   origin;
  for (unsigned int a = 0; a < 3; ++a)
  {
    s[a] = spacing[a];
  }
  for (unsigned int r = 0; r < 3; ++r)
  {
    origin[r] = 0.0;
    for (unsigned int c = 0; c < 3; ++c)
    {
      origin[r] -= direction[r][c] * spacing[c] * 0.5 * (static_cast<double>(size[c]) - 1.0);
    }
  }
  return MakeVolume<TVolume>(size, s, origin, direction);
}

template <typename TVolume>
typename TVolume::DirectionType
Identity()
{
  typename TVolume::DirectionType direction;
  direction.SetIdentity();
  return direction;
}

itk::Vector<double, 3>
Vec3(double x, double y, double z)
{
  itk::Vector<double, 3> v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

/** A deterministic pattern of CT levels (air included) over the whole volume. */
void
FillPattern(HUVolumeType * volume, unsigned int salt = 0)
{
  const short levels[6] = { -1000, -300, 0, 200, 700, 1500 };
  auto *      buffer = volume->GetBufferPointer();
  const auto  count = volume->GetBufferedRegion().GetNumberOfPixels();
  for (size_t v = 0; v < count; ++v)
  {
    buffer[v] = levels[(v * 7 + v / 5 + salt) % 6];
  }
}

GeometryType::Pointer
MakeGeometry(double         sad,
             double         sid,
             double         gantry,
             unsigned int   cols,
             unsigned int   rows,
             double         du,
             double         dv,
             ProjectionEnum projection = ProjectionEnum::Perspective)
{
  auto geometry = GeometryType::New();
  geometry->SetProjection(projection);
  geometry->SetSourceToIsocenterDistance(sad);
  geometry->SetSourceToDetectorDistance(sid);
  geometry->SetGantryAngleInDegrees(gantry);
  geometry->SetDetectorSize({ { cols, rows } });
  itk::Vector<double, 2> spacing;
  spacing[0] = du;
  spacing[1] = dv;
  geometry->SetDetectorSpacing(spacing);
  return geometry;
}

template <typename TImage>
size_t
CountNonFinite(const TImage * image)
{
  const auto * buffer = image->GetBufferPointer();
  size_t       count = 0;
  for (size_t p = 0; p < image->GetBufferedRegion().GetNumberOfPixels(); ++p)
  {
    count += std::isfinite(static_cast<double>(buffer[p])) ? 0 : 1;
  }
  return count;
}

/** Collects everything ITK would print (warnings included) while it is installed; restores the previous window. */
class CapturingOutputWindow : public itk::OutputWindow
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(CapturingOutputWindow);
  using Self = CapturingOutputWindow;
  using Superclass = itk::OutputWindow;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(CapturingOutputWindow);

  void
  DisplayText(const char * text) override
  {
    const std::lock_guard<std::mutex> lock(m_Mutex);
    m_Text += text;
  }
  void
  DisplayWarningText(const char * text) override
  {
    const std::lock_guard<std::mutex> lock(m_Mutex);
    ++m_NumberOfWarnings;
    m_Text += text;
  }
  std::string
  GetText()
  {
    const std::lock_guard<std::mutex> lock(m_Mutex);
    return m_Text;
  }
  unsigned int
  GetNumberOfWarnings()
  {
    const std::lock_guard<std::mutex> lock(m_Mutex);
    return m_NumberOfWarnings;
  }
  void
  Clear()
  {
    const std::lock_guard<std::mutex> lock(m_Mutex);
    m_Text.clear();
    m_NumberOfWarnings = 0;
  }

protected:
  CapturingOutputWindow() = default;
  ~CapturingOutputWindow() override = default;

private:
  std::mutex   m_Mutex;
  std::string  m_Text;
  unsigned int m_NumberOfWarnings{ 0 };
};

class OutputCapture
{
public:
  OutputCapture() : m_Previous(itk::OutputWindow::GetInstance()), m_Window(CapturingOutputWindow::New())
  {
    itk::OutputWindow::SetInstance(m_Window);
  }
  ~OutputCapture() { itk::OutputWindow::SetInstance(m_Previous); }
  ITK_DISALLOW_COPY_AND_MOVE(OutputCapture);

  CapturingOutputWindow *
  operator->()
  {
    return m_Window.GetPointer();
  }

private:
  itk::OutputWindow::Pointer     m_Previous;
  CapturingOutputWindow::Pointer m_Window;
};

/** Mean and spread over seeds of the point-based outputs. */
struct SeedStatistics
{
  std::vector<double> Mean;
  std::vector<double> Variance; // of one render, observed across seeds
  double              SumMean{ 0.0 };
  double              SumVariance{ 0.0 };
  size_t              NonFinite{ 0 }; // non-finite pixels in either output, over all seeds
  unsigned int        Seeds{ 0 };
};

template <typename TFilter>
SeedStatistics
RenderSeeds(TFilter * drr, unsigned int seeds)
{
  SeedStatistics stats;
  stats.Seeds = seeds;
  std::vector<double> sumOfSquares;
  double              sumOfSumSquares = 0.0;
  for (unsigned int seed = 0; seed < seeds; ++seed)
  {
    drr->SetSeed(5000 + seed);
    drr->Update();
    stats.NonFinite += CountNonFinite(drr->GetOutput()) + CountNonFinite(drr->GetStandardErrorOutput());
    const auto values = ToVector(drr->GetOutput());
    if (stats.Mean.empty())
    {
      stats.Mean.assign(values.size(), 0.0);
      sumOfSquares.assign(values.size(), 0.0);
    }
    double sum = 0.0;
    for (size_t p = 0; p < values.size(); ++p)
    {
      stats.Mean[p] += values[p];
      sumOfSquares[p] += values[p] * values[p];
      sum += values[p];
    }
    stats.SumMean += sum;
    sumOfSumSquares += sum * sum;
  }
  for (size_t p = 0; p < stats.Mean.size(); ++p)
  {
    stats.Mean[p] /= seeds;
  }
  stats.Variance.assign(stats.Mean.size(), 0.0);
  for (size_t p = 0; p < stats.Mean.size(); ++p)
  {
    stats.Variance[p] = std::max(0.0, (sumOfSquares[p] - seeds * stats.Mean[p] * stats.Mean[p]) / (seeds - 1.0));
  }
  stats.SumMean /= seeds;
  stats.SumVariance = std::max(0.0, (sumOfSumSquares - seeds * stats.SumMean * stats.SumMean) / (seeds - 1.0));
  return stats;
}

/** The exact filter's image with k and k / 2 rays per pixel side: the value and its discretization error. */
struct Reference
{
  std::vector<double> Value;
  std::vector<double> Error;
  double              Sum{ 0.0 };
  double              SumError{ 0.0 };
  size_t              NonFinite{ 0 };
};

template <typename TVolume>
Reference
ComputeReference(const TVolume *            volume,
                 GeometryType *             geometry,
                 KernelEnum                 kernel,
                 const Configure<TVolume> & configure,
                 unsigned int               raysPerSide)
{
  auto exact = ExactFilter<TVolume>::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->SetReconstructionKernel(kernel);
  if (configure)
  {
    configure(exact.GetPointer());
  }
  exact->SetRaysPerPixelSide(raysPerSide);
  exact->Update();
  Reference reference;
  reference.NonFinite += CountNonFinite(exact->GetOutput());
  reference.Value = ToVector(exact->GetOutput());
  exact->SetRaysPerPixelSide(raysPerSide / 2);
  exact->Update();
  reference.NonFinite += CountNonFinite(exact->GetOutput());
  const auto coarse = ToVector(exact->GetOutput());
  double     coarseSum = 0.0;
  reference.Error.resize(coarse.size());
  for (size_t p = 0; p < coarse.size(); ++p)
  {
    reference.Error[p] = std::abs(reference.Value[p] - coarse[p]);
    reference.Sum += reference.Value[p];
    coarseSum += coarse[p];
  }
  reference.SumError = std::abs(reference.Sum - coarseSum);
  return reference;
}

/** z of a mean over seeds against the reference, with a float-rounding floor (relative 1e-6 of scale). */
double
ZScore(double mean, double varianceOfOne, unsigned int seeds, double reference, double referenceError, double scale)
{
  const double floor = 1e-6 * scale;
  return std::abs(mean - reference) /
         std::sqrt(varianceOfOne / seeds + referenceError * referenceError + floor * floor);
}

struct MatchOptions
{
  KernelEnum   Kernel{ KernelEnum::Box };
  uint64_t     Samples{ 100000 };
  unsigned int Seeds{ 32 };
  unsigned int RaysPerSide{ 0 }; // 0: 64 for the box model (kinks in the line integral), 32 for the tent model
  size_t       BrightPixels{ 6 };
  bool         AllPixels{ false };
  // Largest standard error (relative) of the image-sum comparison for the test to keep its power.
  double SumPower{ 0.01 };
};

/** The point-based mean over seeds matches the exact reference: image sum, the brightest pixels (or all). */
template <typename TVolume>
void
ExpectMatchesExact(const TVolume *            volume,
                   GeometryType *             geometry,
                   const Configure<TVolume> & configure,
                   const MatchOptions &       options,
                   const std::string &        context)
{
  const unsigned int raysPerSide =
    options.RaysPerSide > 0 ? options.RaysPerSide : (options.Kernel == KernelEnum::Box ? 64 : 32);
  const Reference reference = ComputeReference(volume, geometry, options.Kernel, configure, raysPerSide);
  EXPECT_EQ(reference.NonFinite, 0u) << context << ": the exact filter wrote non-finite pixels";
  ASSERT_GT(reference.Sum, 0.0) << context << ": no signal in the reference";

  auto drr = PointBasedFilter<TVolume>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetReconstructionKernel(options.Kernel);
  drr->SetNumberOfSamples(options.Samples);
  if (configure)
  {
    configure(drr.GetPointer());
  }
  const SeedStatistics stats = RenderSeeds(drr.GetPointer(), options.Seeds);
  EXPECT_EQ(stats.NonFinite, 0u) << context << ": the point-based filter wrote non-finite pixels";

  const double sumZ =
    ZScore(stats.SumMean, stats.SumVariance, stats.Seeds, reference.Sum, reference.SumError, std::abs(reference.Sum));
  EXPECT_LT(sumZ, zBound) << context << ": image sum " << stats.SumMean << " vs exact " << reference.Sum
                          << " (standard error of the mean " << std::sqrt(stats.SumVariance / stats.Seeds)
                          << ", reference error " << reference.SumError << ")";
  EXPECT_LT(std::sqrt(stats.SumVariance / stats.Seeds + reference.SumError * reference.SumError),
            options.SumPower * reference.Sum)
    << context << ": the image-sum comparison lost its power";

  const double        peak = *std::max_element(reference.Value.begin(), reference.Value.end());
  std::vector<size_t> order(reference.Value.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return reference.Value[a] > reference.Value[b]; });
  const size_t checked = options.AllPixels ? order.size() : std::min(options.BrightPixels, order.size());
  for (size_t rank = 0; rank < checked; ++rank)
  {
    const size_t p = order[rank];
    if (options.AllPixels && stats.Variance[p] == 0.0 && stats.Mean[p] == 0.0)
    {
      // Never reached in any seed: acceptable only where the reference is (nearly) zero.
      EXPECT_LT(reference.Value[p], 1e-3 * peak) << context << ": pixel " << p << " never reached";
      continue;
    }
    const double z =
      ZScore(stats.Mean[p], stats.Variance[p], stats.Seeds, reference.Value[p], reference.Error[p], peak);
    EXPECT_LT(z, zBound) << context << ": pixel " << p << " mean " << stats.Mean[p] << " vs exact "
                         << reference.Value[p] << " (standard error of the mean "
                         << std::sqrt(stats.Variance[p] / stats.Seeds) << ", reference error " << reference.Error[p]
                         << ")";
    if (!options.AllPixels)
    {
      EXPECT_LT(std::sqrt(stats.Variance[p] / stats.Seeds + reference.Error[p] * reference.Error[p]),
                0.05 * reference.Value[p])
        << context << ": pixel " << p << " comparison lost its power";
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// Bad input, for both filters.

struct PointBasedTag
{
  template <typename TVolume, typename TOutput = ProjectionType>
  using Filter = itk::PointBasedDRRImageFilter<TVolume, TOutput>;
  static constexpr bool IsPointBased = true;
  static std::string
  Name()
  {
    return "PointBased";
  }
};

struct ExactTag
{
  template <typename TVolume, typename TOutput = ProjectionType>
  using Filter = itk::ExactDRRImageFilter<TVolume, TOutput>;
  static constexpr bool IsPointBased = false;
  static std::string
  Name()
  {
    return "Exact";
  }
};

struct TagNames
{
  template <typename T>
  static std::string
  GetName(int)
  {
    return T::Name();
  }
};

using FilterTags = testing::Types<PointBasedTag, ExactTag>;

template <typename TTag>
class PointBasedDRRRobustnessBadInput : public testing::Test
{
public:
  /** A filter of the tag's kind on a small valid problem: 16 x 16 detector, few samples. */
  template <typename TVolume, typename TOutput = ProjectionType>
  static auto
  MakeFilter(const TVolume * volume)
  {
    auto filter = TTag::template Filter<TVolume, TOutput>::New();
    if (volume)
    {
      filter->SetInput(volume);
    }
    filter->SetGeometry(MakeGeometry(100.0, 150.0, 0.0, 16, 16, 2.0, 2.0));
    if constexpr (TTag::IsPointBased)
    {
      filter->SetNumberOfSamples(20000);
    }
    return filter;
  }

  static HUVolumeType::Pointer
  MakeHU()
  {
    auto volume = MakeCentredVolume<HUVolumeType>({ { 6, 5, 4 } }, Vec3(2.0, 2.0, 2.0), Identity<HUVolumeType>());
    FillPattern(volume);
    return volume;
  }

  static MuVolumeType::Pointer
  MakeMu()
  {
    auto volume = MakeCentredVolume<MuVolumeType>({ { 4, 5, 6 } }, Vec3(2.0, 2.0, 2.0), Identity<MuVolumeType>());
    volume->FillBuffer(0.02f);
    return volume;
  }
};

TYPED_TEST_SUITE(PointBasedDRRRobustnessBadInput, FilterTags, TagNames);

TYPED_TEST(PointBasedDRRRobustnessBadInput, EmptyInputRegionThrows)
{
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    HUVolumeType::SizeType size = { { 4, 4, 4 } };
    size[axis] = 0;
    auto volume = MakeCentredVolume<HUVolumeType>(size, Vec3(1.0, 1.0, 1.0), Identity<HUVolumeType>());
    auto filter = TestFixture::MakeFilter(volume.GetPointer());
    ExpectUpdateThrows(filter.GetPointer(), { "empty" }, "size 0 along axis " + std::to_string(axis));
  }
}

TYPED_TEST(PointBasedDRRRobustnessBadInput, NoInputThrows)
{
  auto filter = TestFixture::template MakeFilter<HUVolumeType>(nullptr);
  ExpectUpdateThrows(filter.GetPointer(), { "input" }, "no input");
}

TYPED_TEST(PointBasedDRRRobustnessBadInput, NonFiniteVoxelsThrowNamingTheVoxel)
{
  const float values[3] = { std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity() };
  for (float value : values)
  {
    auto volume = TestFixture::MakeMu();
    volume->SetPixel({ { 1, 2, 3 } }, value);
    auto filter = TestFixture::MakeFilter(volume.GetPointer());
    filter->GetTransferFunction()->SetMode(TransferEnum::Identity);
    ExpectUpdateThrows(
      filter.GetPointer(), { "non-finite", "voxel (1, 2, 3)" }, "voxel value " + std::to_string(value));
  }
}

TYPED_TEST(PointBasedDRRRobustnessBadInput, NegativeMuWithIdentityThrowsNamingTheVoxel)
{
  auto volume = TestFixture::MakeMu();
  volume->SetPixel({ { 2, 1, 0 } }, -0.01f);
  auto filter = TestFixture::MakeFilter(volume.GetPointer());
  filter->GetTransferFunction()->SetMode(TransferEnum::Identity);
  ExpectUpdateThrows(filter.GetPointer(), { "negative", "voxel (2, 1, 0)" }, "negative mu");
}

TYPED_TEST(PointBasedDRRRobustnessBadInput, InvalidGeometryThrowsNamingTheParameter)
{
  const auto volume = TestFixture::MakeHU();
  struct Case
  {
    std::string                         name;
    std::function<void(GeometryType *)> spoil;
    std::vector<std::string>            keywords;
  };
  const std::vector<Case> cases = {
    { "SID 0", [](GeometryType * g) { g->SetSourceToDetectorDistance(0.0); }, { "SID" } },
    { "SID < 0", [](GeometryType * g) { g->SetSourceToDetectorDistance(-150.0); }, { "SID" } },
    { "SAD 0", [](GeometryType * g) { g->SetSourceToIsocenterDistance(0.0); }, { "SAD" } },
    { "SAD < 0", [](GeometryType * g) { g->SetSourceToIsocenterDistance(-100.0); }, { "SAD" } },
    { "du 0",
      [](GeometryType * g) {
        itk::Vector<double, 2>s;
        s[0] = 0.0;
        s[1] = 1.0;
        g->SetDetectorSpacing(s);
      },
      { "spacing", "du" } },
    { "dv < 0",
      [](GeometryType * g) {
        itk::Vector<double, 2>s;
        s[0] = 1.0;
        s[1] = -1.0;
        g->SetDetectorSpacing(s);
      },
      { "spacing", "dv" } },
    { "0 columns",
      [](GeometryType * g) {
        g->SetDetectorSize({ { 0, 16 } });
      },
      { "zero", "columns" } },
    { "0 rows",
      [](GeometryType * g) {
        g->SetDetectorSize({ { 16, 0 } });
      },
      { "zero", "rows" } },
    { "vup along nrm", [](GeometryType * g) { g->SetViewUp(Vec3(3.0, 0.0, 0.0)); }, { "vup", "parallel" } },
    { "vup against nrm", [](GeometryType * g) { g->SetViewUp(Vec3(-1.0, 0.0, 0.0)); }, { "vup", "parallel" } },
  };
  for (const auto & c : cases)
  {
    auto filter = TestFixture::MakeFilter(volume.GetPointer());
    ASSERT_NEAR(filter->GetGeometry()->GetNormal()[0], 1.0, 1e-12); // gantry 0: nrm = +x
    c.spoil(filter->GetGeometry());
    ExpectUpdateThrows(filter.GetPointer(), c.keywords, c.name);
  }
}

TYPED_TEST(PointBasedDRRRobustnessBadInput, NonLinearTransformThrows)
{
  const auto volume = TestFixture::MakeHU();
  auto       filter = TestFixture::MakeFilter(volume.GetPointer());
  auto       bspline = itk::BSplineTransform<double, 3, 3>::New();
  ASSERT_FALSE(bspline->IsLinear());
  filter->SetTransform(bspline);
  ExpectUpdateThrows(filter.GetPointer(), { "not linear" }, "B-spline transform");
}

TYPED_TEST(PointBasedDRRRobustnessBadInput, SingularAffineTransformThrows)
{
  const auto volume = TestFixture::MakeHU();
  auto       filter = TestFixture::MakeFilter(volume.GetPointer());
  auto       affine = itk::AffineTransform<double, 3>::New();
  auto       matrix = affine->GetMatrix();
  matrix[1][0] = 0.0;
  matrix[1][1] = 0.0;
  matrix[1][2] = 0.0; // a zero row
  affine->SetMatrix(matrix);
  filter->SetTransform(affine);
  ExpectUpdateThrows(filter.GetPointer(), { "singular" }, "singular affine");
}

TYPED_TEST(PointBasedDRRRobustnessBadInput, IntegerOutputNeedsAGrayMode)
{
  const auto volume = TestFixture::MakeHU();
  auto       lineIntegral = TestFixture::template MakeFilter<HUVolumeType, GrayProjectionType>(volume.GetPointer());
  ExpectUpdateThrows(lineIntegral.GetPointer(), { "integer" }, "unsigned char output, LineIntegral mode");

  // Gray8 into unsigned char works, and is the float line-integral image windowed by the automatic window (its 0.5th to
  // 99.5th percentile, sorted values at floor(q (n - 1))), clamped outside it.
  auto reference = TestFixture::template MakeFilter<HUVolumeType, ProjectionType>(volume.GetPointer());
  reference->Update();
  const auto lineIntegrals = ToVector(reference->GetOutput());
  auto       gray = TestFixture::template MakeFilter<HUVolumeType, GrayProjectionType>(volume.GetPointer());
  gray->SetOutputMode(OutputModeEnum::Gray8);
  ASSERT_NO_THROW(gray->Update()) << "Gray8 into an unsigned char image must work";
  const auto          levels = ToVector(gray->GetOutput());
  std::vector<double> sorted(lineIntegrals.begin(), lineIntegrals.end());
  std::sort(sorted.begin(), sorted.end());
  const double low = sorted[static_cast<size_t>(0.005 * static_cast<double>(sorted.size() - 1))];
  const double high = sorted[static_cast<size_t>(0.995 * static_cast<double>(sorted.size() - 1))];
  ASSERT_GT(high, low);
  ASSERT_EQ(levels.size(), lineIntegrals.size());
  for (size_t p = 0; p < levels.size(); ++p)
  {
    EXPECT_GE(levels[p], 0.0);
    EXPECT_LE(levels[p], 255.0);
    const double position = std::min(1.0, std::max(0.0, (lineIntegrals[p] - low) / (high - low)));
    EXPECT_NEAR(levels[p], std::floor(position * 255.0 + 0.5), 1.0) << "pixel " << p;
  }
  EXPECT_EQ(*std::min_element(levels.begin(), levels.end()), 0.0);
  EXPECT_EQ(*std::max_element(levels.begin(), levels.end()), 255.0);
}

TEST(PointBasedDRRRobustness, ZeroSamplesThrows)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 4, 4, 4 } }, Vec3(1.0, 1.0, 1.0), Identity<HUVolumeType>());
  FillPattern(volume);
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(100.0, 150.0, 0.0, 8, 8, 2.0, 2.0));
  drr->SetNumberOfSamples(0);
  ExpectUpdateThrows(drr.GetPointer(), { "number of samples" }, "N = 0");
}

TEST(PointBasedDRRRobustness, OneStratumIsRefusedAndTooFewPointsPerStratumWarn)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 4, 4, 4 } }, Vec3(1.0, 1.0, 1.0), Identity<HUVolumeType>());
  FillPattern(volume);
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(100.0, 150.0, 0.0, 8, 8, 2.0, 2.0));
  drr->SetSampler(itk::DRRSamplerFactory::Create("stratified"));
  drr->SetNumberOfStrata(1);
  ExpectUpdateThrows(drr.GetPointer(), { "NumberOfStrata", "not 1" }, "R = 1");
  // 4 strata of fewer than 16 points: one run, and a warning that its standard error assumes independence.
  drr->SetNumberOfStrata(4);
  drr->SetNumberOfSamples(40);
  OutputCapture capture;
  ASSERT_NO_THROW(drr->Update());
  EXPECT_EQ(capture->GetNumberOfWarnings(), 1u);
  EXPECT_NE(capture->GetText().find("too few for 4 strata"), std::string::npos) << capture->GetText();
  // Enough points: no warning.
  capture->Clear();
  drr->SetNumberOfSamples(64);
  drr->Update();
  EXPECT_EQ(capture->GetNumberOfWarnings(), 0u) << capture->GetText();
}

// ---------------------------------------------------------------------------------------------------------------------
// Numerical extremes (docs/design.md section 8).

TEST(PointBasedDRRExtremes, AllAirIsExactlyZero)
{
  for (short air : { short{ -1000 }, short{ -3024 } })
  {
    auto volume = MakeCentredVolume<HUVolumeType>({ { 8, 7, 6 } }, Vec3(1.5, 1.5, 2.0), Identity<HUVolumeType>());
    volume->FillBuffer(air);
    for (auto projection : { ProjectionEnum::Perspective, ProjectionEnum::Parallel })
    {
      for (auto kernel : { KernelEnum::Box, KernelEnum::Tent })
      {
        const std::string context = "HU " + std::to_string(air) +
                                    (projection == ProjectionEnum::Parallel ? " parallel" : " perspective") +
                                    (kernel == KernelEnum::Box ? " box" : " tent");
        auto geometry = MakeGeometry(100.0, 150.0, 30.0, 16, 16, 1.5, 1.5, projection);
        auto drr = PointBasedFilter<HUVolumeType>::New();
        drr->SetInput(volume);
        drr->SetGeometry(geometry);
        drr->SetReconstructionKernel(kernel);
        drr->SetSplat(kernel == KernelEnum::Box ? SplatEnum::Nearest : SplatEnum::Bilinear);
        drr->SetNumberOfSamples(10000);
        drr->Update();
        EXPECT_EQ(drr->GetTotalMass(), 0.0) << context;
        EXPECT_EQ(drr->GetPointsOnDetector(), 0u) << context;
        for (const float value : ToVector(drr->GetOutput()))
        {
          ASSERT_EQ(value, 0.0f) << context;
        }
        for (const float value : ToVector(drr->GetStandardErrorOutput()))
        {
          ASSERT_EQ(value, 0.0f) << context;
        }
        auto exact = ExactFilter<HUVolumeType>::New();
        exact->SetInput(volume);
        exact->SetGeometry(geometry);
        exact->SetReconstructionKernel(kernel);
        exact->SetRaysPerPixelSide(2);
        exact->Update();
        for (const float value : ToVector(exact->GetOutput()))
        {
          ASSERT_EQ(value, 0.0f) << context;
        }
        // Derived output modes of a zero image stay finite: exp(0) = 1, gray levels of an empty range.
        drr->SetOutputMode(OutputModeEnum::Transmission);
        drr->Update();
        for (const float value : ToVector(drr->GetOutput()))
        {
          ASSERT_EQ(value, 1.0f) << context;
        }
        drr->SetOutputMode(OutputModeEnum::Gray16);
        drr->Update();
        EXPECT_EQ(CountNonFinite(drr->GetOutput()), 0u) << context;
      }
    }
  }
  // mu input, all zero.
  auto volume = MakeCentredVolume<MuVolumeType>({ { 5, 5, 5 } }, Vec3(1.0, 1.0, 1.0), Identity<MuVolumeType>());
  auto drr = PointBasedFilter<MuVolumeType>::New();
  drr->SetInput(volume);
  drr->GetTransferFunction()->SetMode(TransferEnum::Identity);
  drr->SetGeometry(MakeGeometry(100.0, 150.0, 0.0, 8, 8, 2.0, 2.0));
  drr->Update();
  for (const float value : ToVector(drr->GetOutput()))
  {
    ASSERT_EQ(value, 0.0f);
  }
  for (const float value : ToVector(drr->GetStandardErrorOutput()))
  {
    ASSERT_EQ(value, 0.0f);
  }
  // The filters draw nothing from such a model; a level sampler asked for a batch of it directly refuses, instead of
  // reading tables that are not there.
  for (const std::string name : { "level-alias", "paper-hybrid" })
  {
    auto sampler = itk::DRRSamplerFactory::Create(name);
    sampler->Initialize(*drr->GetAttenuationVolume());
    uint64_t                          voxel[16];
    double                            weight[16];
    itk::DRRPointSampler::SampleRange range;
    range.Count = 16;
    range.StratumSize = 16;
    itk::detail::DRRPhiloxRandom random(1, 0, 0);
    EXPECT_NE(ExceptionMessage([&] { sampler->GenerateBatch(random, range, voxel, weight); }, name).find("all air"),
              std::string::npos)
      << name;
  }
}

TEST(PointBasedDRRExtremes, SingleVoxelMatchesExactProjector)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 1, 1, 1 } }, Vec3(2.0, 3.0, 4.0), Identity<HUVolumeType>());
  volume->FillBuffer(1000);
  const double mass = MuOfHU(1000.0) * 2.0 * 3.0 * 4.0;
  for (auto kernel : { KernelEnum::Box, KernelEnum::Tent })
  {
    auto         geometry = MakeGeometry(100.0, 200.0, 30.0, 16, 16, 1.0, 1.0);
    MatchOptions options;
    options.Kernel = kernel;
    options.Samples = 50000;
    ExpectMatchesExact<HUVolumeType>(
      volume, geometry, nullptr, options, kernel == KernelEnum::Box ? "single voxel, box" : "single voxel, tent");
  }
  // Parallel beam onto a detector that holds the whole shadow: every point lands with weight 1, so the image sum is
  // M / a exactly.
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(100.0, 200.0, 30.0, 16, 16, 1.0, 1.0, ProjectionEnum::Parallel));
  drr->SetNumberOfSamples(10000);
  drr->Update();
  const auto image = ToVector(drr->GetOutput());
  EXPECT_EQ(drr->GetPointsOnDetector(), 10000u);
  EXPECT_NEAR(drr->GetTotalMass(), mass, 1e-9 * mass);
  EXPECT_NEAR(std::accumulate(image.begin(), image.end(), 0.0), mass / 1.0, 1e-6 * mass);
}

TEST(PointBasedDRRExtremes, OneByOneByFortyMatchesExactProjector)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 1, 1, 40 } }, Vec3(1.5, 1.5, 0.5), Identity<HUVolumeType>());
  for (unsigned int k = 0; k < 40; ++k)
  {
    volume->SetPixel({ { 0, 0, k } }, static_cast<short>((k * 53) % 1500 - 200));
  }
  for (double gantry : { 0.0, 37.0 })
  {
    auto         geometry = MakeGeometry(100.0, 150.0, gantry, 8, 16, 1.0, 3.0);
    MatchOptions options;
    ExpectMatchesExact<HUVolumeType>(
      volume, geometry, nullptr, options, "1 x 1 x 40, gantry " + std::to_string(gantry));
  }
}

TEST(PointBasedDRRExtremes, OneSampleIsOnePointOfWeightMOverA)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 3, 3, 3 } }, Vec3(2.0, 2.0, 2.0), Identity<HUVolumeType>());
  FillPattern(volume, 1);
  double mass = 0.0;
  for (size_t v = 0; v < 27; ++v)
  {
    mass += MuOfHU(volume->GetBufferPointer()[v]) * 8.0;
  }
  ASSERT_GT(mass, 0.0);
  const double pixelArea = 1.5 * 1.5;
  for (auto projection : { ProjectionEnum::Parallel, ProjectionEnum::Perspective })
  {
    const double sad = 100.0, sid = 150.0;
    auto         geometry = MakeGeometry(sad, sid, 20.0, 16, 16, 1.5, 1.5, projection);
    // Bounds of the perspective weight (SID / z)^2 sqrt(1 + tan^2) over the voxel box [-3, 3]^3 around the isocenter.
    const double half = 3.0 * std::sqrt(3.0);
    const double zNear = sad - half, zFar = sad + half;
    const double tanMax = (half + half) / zNear;
    const double lowest = projection == ProjectionEnum::Parallel ? 1.0 : (sid / zFar) * (sid / zFar);
    const double highest = projection == ProjectionEnum::Parallel
                             ? 1.0
                             : (sid / zNear) * (sid / zNear) * std::sqrt(1.0 + 2.0 * tanMax * tanMax);
    auto         drr = PointBasedFilter<HUVolumeType>::New();
    drr->SetInput(volume);
    drr->SetGeometry(geometry);
    drr->SetNumberOfSamples(1);
    for (uint64_t seed = 0; seed < 8; ++seed)
    {
      drr->SetSeed(seed);
      drr->Update();
      const auto image = ToVector(drr->GetOutput());
      const auto errors = ToVector(drr->GetStandardErrorOutput());
      EXPECT_EQ(CountNonFinite(drr->GetOutput()), 0u);
      EXPECT_EQ(CountNonFinite(drr->GetStandardErrorOutput()), 0u) << "standard error of N = 1";
      EXPECT_EQ(drr->GetPointsOnDetector(), 1u) << "the detector holds the whole shadow";
      size_t nonZero = 0;
      double weight = 0.0;
      for (size_t p = 0; p < image.size(); ++p)
      {
        if (image[p] != 0.0)
        {
          ++nonZero;
          weight = image[p] * pixelArea / mass;
        }
        else
        {
          EXPECT_EQ(errors[p], 0.0);
        }
        EXPECT_GE(errors[p], 0.0);
      }
      EXPECT_EQ(nonZero, 1u) << "one point, nearest splat";
      if (projection == ProjectionEnum::Parallel)
      {
        EXPECT_NEAR(weight, 1.0, 1e-6) << "parallel: the one pixel holds M / (N a)";
      }
      else
      {
        EXPECT_GE(weight, lowest * (1.0 - 1e-6)) << "seed " << seed;
        EXPECT_LE(weight, highest * (1.0 + 1e-6)) << "seed " << seed;
      }
    }
  }
}

TEST(PointBasedDRRExtremes, HUExtremesGiveNonNegativeMuAndMatchExact)
{
  const short extremes[7] = { -32768, -3024, -2048, -1024, 3071, 20000, 32767 };
  auto        volume = MakeCentredVolume<HUVolumeType>({ { 7, 6, 5 } }, Vec3(2.0, 2.0, 2.0), Identity<HUVolumeType>());
  auto *      buffer = volume->GetBufferPointer();
  for (size_t v = 0; v < 7 * 6 * 5; ++v)
  {
    buffer[v] = extremes[(v * 3 + v / 7) % 7];
  }
  auto geometry = MakeGeometry(100.0, 150.0, 25.0, 16, 16, 1.5, 1.5);
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetNumberOfSamples(1000);
  ASSERT_NO_THROW(drr->Update());
  const itk::DRRAttenuationVolume * attenuation = drr->GetAttenuationVolume();
  ASSERT_EQ(attenuation->GetNumberOfVoxels(), 7u * 6u * 5u);
  for (size_t v = 0; v < 7 * 6 * 5; ++v)
  {
    const double mu = attenuation->GetMuBuffer()[v];
    EXPECT_GE(mu, 0.0) << "HU " << buffer[v];
    EXPECT_NEAR(mu, MuOfHU(buffer[v]), 1e-7 * (1.0 + mu)) << "HU " << buffer[v];
  }
  MatchOptions options;
  ExpectMatchesExact<HUVolumeType>(volume, geometry, nullptr, options, "HU extremes");
}

TEST(PointBasedDRRExtremes, MuInputOverThirtyDecadesMatchesExact)
{
  // Continuous mu (Identity transfer function) from denormal floats to 0.5 /mm, with air: the sampler bins it and
  // weights each point by mu_v / (mean mu of its bin); the estimate must stay finite and unbiased.
  auto   volume = MakeCentredVolume<MuVolumeType>({ { 9, 8, 7 } }, Vec3(1.5, 1.5, 1.5), Identity<MuVolumeType>());
  auto * buffer = volume->GetBufferPointer();
  for (size_t v = 0; v < 9 * 8 * 7; ++v)
  {
    const unsigned int r = static_cast<unsigned int>((v * 2654435761u) >> 7);
    buffer[v] = v % 6 == 0
                  ? 0.0f
                  : static_cast<float>(0.5 * std::pow(10.0, -static_cast<double>(r % 31)) * (0.5 + (r % 97) / 97.0));
  }
  buffer[10] = std::numeric_limits<float>::denorm_min();
  buffer[11] = std::numeric_limits<float>::min();
  buffer[12] = 0.5f;
  const Configure<MuVolumeType> identity = [](FilterBase<MuVolumeType> * f) {
    f->GetTransferFunction()->SetMode(TransferEnum::Identity);
  };
  auto         geometry = MakeGeometry(100.0, 150.0, 50.0, 16, 16, 1.5, 1.5);
  MatchOptions options;
  ExpectMatchesExact<MuVolumeType>(volume, geometry, identity, options, "mu over 30 decades");
}

TEST(PointBasedDRRExtremes, AnisotropicObliqueAndLeftHandedVoxelsMatchExactTent)
{
  const auto                  axis = Vec3(1.0 / std::sqrt(14.0), 2.0 / std::sqrt(14.0), 3.0 / std::sqrt(14.0));
  HUVolumeType::DirectionType rotated;
  rotated = RotationMatrix(axis, 35.0);
  HUVolumeType::DirectionType leftHanded = rotated;
  for (unsigned int r = 0; r < 3; ++r)
  {
    leftHanded[r][2] = -rotated[r][2];
  }
  ASSERT_LT(vnl_det(leftHanded.GetVnlMatrix()), -0.999);
  for (const auto & direction : { rotated, leftHanded })
  {
    auto volume = MakeCentredVolume<HUVolumeType>({ { 16, 16, 4 } }, Vec3(0.3, 0.3, 5.0), direction);
    FillPattern(volume, 2);
    // A bright off-centre rod so that the image is not symmetric under the flip.
    FillBlock<HUVolumeType>(volume, { { 2, 3, 0 } }, { { 5, 6, 2 } }, 2500);
    auto         geometry = MakeGeometry(100.0, 160.0, 20.0, 12, 12, 3.0, 3.0);
    MatchOptions options;
    options.Kernel = KernelEnum::Tent;
    const bool left = vnl_det(direction.GetVnlMatrix()) < 0.0;
    ExpectMatchesExact<HUVolumeType>(
      volume, geometry, nullptr, options, left ? "0.3 x 0.3 x 5, left-handed" : "0.3 x 0.3 x 5, rotated");
  }
}

TEST(PointBasedDRRExtremes, SourceNextToOnOrInsideTheVolumeWarnsAndStaysFinite)
{
  // A 20 mm cube centred on the isocenter: its near face (box model) is at x = +10; the source is at x = SAD.
  auto volume = MakeCentredVolume<HUVolumeType>({ { 16, 16, 16 } }, Vec3(1.25, 1.25, 1.25), Identity<HUVolumeType>());
  FillPattern(volume, 3);
  struct Case
  {
    const char * name;
    double       sad;
  };
  for (const Case & c : { Case{ "a micrometre from the surface", 10.001 },
                          Case{ "on the surface", 10.0 },
                          Case{ "inside", 4.0 },
                          Case{ "at the centre", 1e-9 } })
  {
    auto geometry = MakeGeometry(c.sad, c.sad + 30.0, 0.0, 16, 16, 5.0, 5.0);
    auto drr = PointBasedFilter<HUVolumeType>::New();
    drr->SetInput(volume);
    drr->SetGeometry(geometry);
    drr->SetNumberOfSamples(100000);
    OutputCapture capture;
    ASSERT_NO_THROW(drr->Update()) << c.name;
    EXPECT_GE(capture->GetNumberOfWarnings(), 1u) << c.name << ": no warning";
    EXPECT_NE(Lower(capture->GetText()).find("source"), std::string::npos)
      << c.name << ": the warning does not mention the source: " << capture->GetText();
    EXPECT_EQ(CountNonFinite(drr->GetOutput()), 0u) << c.name;
    EXPECT_EQ(CountNonFinite(drr->GetStandardErrorOutput()), 0u) << c.name;
    const auto image = ToVector(drr->GetOutput());
    EXPECT_GE(*std::min_element(image.begin(), image.end()), 0.0) << c.name;
    EXPECT_GT(*std::max_element(image.begin(), image.end()), 0.0) << c.name << ": no signal at all";
    for (auto kernel : { KernelEnum::Box, KernelEnum::Tent })
    {
      auto exact = ExactFilter<HUVolumeType>::New();
      exact->SetInput(volume);
      exact->SetGeometry(geometry);
      exact->SetReconstructionKernel(kernel);
      exact->SetRaysPerPixelSide(3);
      exact->Update();
      EXPECT_EQ(CountNonFinite(exact->GetOutput()), 0u) << c.name;
    }
  }
  // Control: at a normal distance there is no warning.
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(100.0, 150.0, 0.0, 16, 16, 5.0, 5.0));
  drr->SetNumberOfSamples(100000);
  OutputCapture capture;
  drr->Update();
  EXPECT_EQ(capture->GetText(), "") << "a warning at SAD 100 mm";
}

TEST(PointBasedDRRExtremes, DetectorPlaneCuttingTheVolumeMatchesExact)
{
  // A 20 mm cube centred on the isocenter at SAD 100: its faces are at depth 90 and 110.
  auto volume = MakeCentredVolume<HUVolumeType>({ { 10, 10, 10 } }, Vec3(2.0, 2.0, 2.0), Identity<HUVolumeType>());
  FillPattern(volume, 4);
  for (double sid : { 100.0, 94.0 })
  {
    auto         geometry = MakeGeometry(100.0, sid, 15.0, 14, 14, 2.0, 2.0);
    MatchOptions options;
    ExpectMatchesExact<HUVolumeType>(volume, geometry, nullptr, options, "SID " + std::to_string(sid));
  }
  // The cut is real: the exact image with the detector at 100 mm holds clearly less than with the detector behind.
  // Image sum * a / SID^2 is the integral of mu / z^2 * obliquity over the part of the volume before the detector;
  // both detectors hold the whole shadow.
  auto         cut = MakeGeometry(100.0, 100.0, 15.0, 16, 16, 4.0, 4.0);
  auto         whole = MakeGeometry(100.0, 150.0, 15.0, 16, 16, 6.0, 6.0);
  const auto   cutReference = ComputeReference<HUVolumeType>(volume, cut, KernelEnum::Box, nullptr, 8);
  const auto   wholeReference = ComputeReference<HUVolumeType>(volume, whole, KernelEnum::Box, nullptr, 8);
  const double cutIntegral = cutReference.Sum * 16.0 / (100.0 * 100.0);
  const double wholeIntegral = wholeReference.Sum * 36.0 / (150.0 * 150.0);
  EXPECT_GT(cutIntegral, 0.3 * wholeIntegral);
  EXPECT_LT(cutIntegral, 0.8 * wholeIntegral);
}

TEST(PointBasedDRRExtremes, RaysSixtyDegreesOffAxisMatchExact)
{
  // Source at x = 100 (gantry 0), u = +y. A 12 mm cube at depth 100 and lateral 100 tan 60: its shadow on the
  // detector (SID 200) is around u = 200 tan 60.
  const double tan60 = std::tan(60.0 * itk::Math::pi / 180.0);
  auto         volume = MakeCentredVolume<HUVolumeType>({ { 8, 8, 8 } }, Vec3(1.5, 1.5, 1.5), Identity<HUVolumeType>());
  FillPattern(volume, 5);
  auto origin = volume->GetOrigin();
  origin[1] += 100.0 * tan60;
  volume->SetOrigin(origin);
  auto geometry = MakeGeometry(100.0, 200.0, 0.0, 16, 16, 8.0, 3.0);
  ASSERT_NEAR(geometry->GetColumnDirection()[1], 1.0, 1e-12);
  itk::Vector<double, 2> offset;
  offset[0] = 200.0 * tan60;
  offset[1] = 0.0;
  geometry->SetDetectorOffset(offset);
  MatchOptions options;
  ExpectMatchesExact<HUVolumeType>(volume, geometry, nullptr, options, "60 degrees off-axis");
  options.Kernel = KernelEnum::Tent;
  ExpectMatchesExact<HUVolumeType>(volume, geometry, nullptr, options, "60 degrees off-axis, tent");
}

TEST(PointBasedDRRExtremes, ParallelBeamAlongAVolumeAxisMatchesExact)
{
  // Gantry 0, identity direction: rays run exactly along -x, and the 1.5 mm pixels line up with the voxel faces, so
  // each pixel is one column of voxels and the exact pixel average is exact whatever k.
  auto volume = MakeCentredVolume<HUVolumeType>({ { 8, 8, 8 } }, Vec3(1.5, 1.5, 1.5), Identity<HUVolumeType>());
  FillPattern(volume, 6);
  auto         geometry = MakeGeometry(100.0, 150.0, 0.0, 12, 12, 1.5, 1.5, ProjectionEnum::Parallel);
  MatchOptions options;
  options.AllPixels = true;
  options.Seeds = 48;
  ExpectMatchesExact<HUVolumeType>(volume, geometry, nullptr, options, "parallel along x");
  // The pixel-aligned reference: one ray per pixel already gives the same image as 16 x 16.
  const auto one = ComputeReference<HUVolumeType>(volume, geometry, KernelEnum::Box, nullptr, 2);
  const auto many = ComputeReference<HUVolumeType>(volume, geometry, KernelEnum::Box, nullptr, 16);
  for (size_t p = 0; p < one.Value.size(); ++p)
  {
    EXPECT_NEAR(one.Value[p], many.Value[p], 1e-5 * (1.0 + many.Value[p])) << "pixel " << p;
  }
  // And the image sum is M / a exactly: every point lands with weight 1.
  double mass = 0.0;
  for (size_t v = 0; v < 512; ++v)
  {
    mass += MuOfHU(volume->GetBufferPointer()[v]) * 1.5 * 1.5 * 1.5;
  }
  EXPECT_NEAR(many.Sum, mass / (1.5 * 1.5), 1e-5 * many.Sum);
}

TEST(PointBasedDRRExtremes, HalfTurnTransformMatchesExactAndTheRotatedVolume)
{
  HUVolumeType::SizeType size = { { 8, 6, 5 } };
  auto                   volume = MakeCentredVolume<HUVolumeType>(size, Vec3(1.5, 2.0, 2.5), Identity<HUVolumeType>());
  FillPattern(volume, 7);
  auto origin = volume->GetOrigin();
  origin[0] += 3.0;
  origin[1] -= 2.0;
  volume->SetOrigin(origin);
  auto halfTurn = itk::Euler3DTransform<double>::New();
  halfTurn->SetRotation(0.0, 0.0, itk::Math::pi);
  auto                          geometry = MakeGeometry(100.0, 150.0, 30.0, 14, 14, 2.0, 2.0);
  const Configure<HUVolumeType> withTransform = [&](FilterBase<HUVolumeType> * f) { f->SetTransform(halfTurn); };
  MatchOptions                  options;
  ExpectMatchesExact<HUVolumeType>(volume, geometry, withTransform, options, "Euler 180 degrees about z");

  // The room sees the volume turned by 180 degrees about z: the same as a volume with origin and direction turned.
  auto turned = HUVolumeType::New();
  turned->Graft(volume);
  HUVolumeType::PointType     turnedOrigin = volume->GetOrigin();
  HUVolumeType::DirectionType turnedDirection = volume->GetDirection();
  turnedOrigin[0] = -turnedOrigin[0];
  turnedOrigin[1] = -turnedOrigin[1];
  for (unsigned int c = 0; c < 3; ++c)
  {
    turnedDirection[0][c] = -turnedDirection[0][c];
    turnedDirection[1][c] = -turnedDirection[1][c];
  }
  turned->SetOrigin(turnedOrigin);
  turned->SetDirection(turnedDirection);
  const auto viaTransform = ComputeReference<HUVolumeType>(volume, geometry, KernelEnum::Box, withTransform, 4);
  const auto viaVolume = ComputeReference<HUVolumeType>(turned, geometry, KernelEnum::Box, nullptr, 4);
  ASSERT_GT(viaVolume.Sum, 0.0);
  const double peak = *std::max_element(viaVolume.Value.begin(), viaVolume.Value.end());
  for (size_t p = 0; p < viaVolume.Value.size(); ++p)
  {
    EXPECT_NEAR(viaTransform.Value[p], viaVolume.Value[p], 1e-5 * peak) << "pixel " << p;
  }
  // And it differs from the untransformed image (the phantom is not symmetric under the half turn).
  const auto plain = ComputeReference<HUVolumeType>(volume, geometry, KernelEnum::Box, nullptr, 4);
  double     difference = 0.0;
  for (size_t p = 0; p < plain.Value.size(); ++p)
  {
    difference = std::max(difference, std::abs(plain.Value[p] - viaVolume.Value[p]));
  }
  EXPECT_GT(difference, 0.05 * peak);
}

TEST(PointBasedDRRExtremes, VolumeTranslatedOutOfViewGivesExactZero)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 8, 8, 8 } }, Vec3(1.5, 1.5, 1.5), Identity<HUVolumeType>());
  FillPattern(volume, 8);
  auto geometry = MakeGeometry(100.0, 150.0, 0.0, 16, 16, 2.0, 2.0); // source at x = +100
  struct Case
  {
    const char * name;
    double       translation[3];
  };
  // The transform maps room to volume (x_volume = x_room + t): the volume appears at -t in the room.
  for (const Case & c : { Case{ "2000 mm sideways", { 0.0, 2000.0, 0.0 } },
                          Case{ "2000 mm behind the source", { -2000.0, 0.0, 0.0 } },
                          Case{ "2000 mm beyond the detector", { 2000.0, 0.0, 0.0 } } })
  {
    auto transform = itk::Euler3DTransform<double>::New();
    transform->SetTranslation(Vec3(c.translation[0], c.translation[1], c.translation[2]));
    auto drr = PointBasedFilter<HUVolumeType>::New();
    drr->SetInput(volume);
    drr->SetGeometry(geometry);
    drr->SetTransform(transform);
    drr->SetNumberOfSamples(50000);
    OutputCapture capture;
    drr->Update();
    EXPECT_GT(drr->GetTotalMass(), 0.0) << c.name;
    EXPECT_EQ(drr->GetPointsOnDetector(), 0u) << c.name;
    for (const float value : ToVector(drr->GetOutput()))
    {
      ASSERT_EQ(value, 0.0f) << c.name;
    }
    for (const float value : ToVector(drr->GetStandardErrorOutput()))
    {
      ASSERT_EQ(value, 0.0f) << c.name;
    }
    // Nothing of the volume is near the source: a "source next to the volume" warning would be false.
    EXPECT_EQ(capture->GetText(), "") << c.name << ": spurious warning";
    auto exact = ExactFilter<HUVolumeType>::New();
    exact->SetInput(volume);
    exact->SetGeometry(geometry);
    exact->SetTransform(transform);
    exact->SetRaysPerPixelSide(2);
    exact->Update();
    for (const float value : ToVector(exact->GetOutput()))
    {
      ASSERT_EQ(value, 0.0f) << c.name;
    }
  }
}

TEST(PointBasedDRRExtremes, MetresOfTranslationAndHalfTurnsAboutEveryAxisMatchExact)
{
  // The volume carried 1.5 m towards a far detector (SAD 1000 mm, SID 3000 mm, source at x = +1000) and turned by
  // half turns about x and z and a quarter turn about y: still in the beam, 2.5 m from the source.
  auto volume = MakeCentredVolume<HUVolumeType>({ { 8, 7, 6 } }, Vec3(1.5, 2.0, 2.5), Identity<HUVolumeType>());
  FillPattern(volume, 11);
  FillBlock<HUVolumeType>(volume, { { 0, 0, 0 } }, { { 2, 1, 1 } }, 2000); // not symmetric under the turns
  auto transform = itk::Euler3DTransform<double>::New();
  transform->SetRotation(itk::Math::pi, itk::Math::pi_over_2, -itk::Math::pi);
  // Room -> volume, x_volume = R x_room + t: with t = R (1500, 0, 0) the volume's centre appears at x = -1500 mm.
  transform->SetTranslation(transform->GetMatrix() * Vec3(1500.0, 0.0, 0.0));
  auto                          geometry = MakeGeometry(1000.0, 3000.0, 0.0, 12, 12, 4.0, 4.0);
  const Configure<HUVolumeType> withTransform = [&](FilterBase<HUVolumeType> * f) { f->SetTransform(transform); };
  MatchOptions                  options;
  options.AllPixels = true;
  ExpectMatchesExact<HUVolumeType>(volume, geometry, withTransform, options, "1.5 m and half turns");
  // The volume really is where the transform says, 2.5 m from the source: image sum * a = integral over the volume
  // of mu w, w = (SID / z)^2 sqrt(SID^2 + u^2 + v^2) / SID, by a midpoint rule on 4^3 points per voxel placed in the
  // room by the inverse transform (independent of the filters' projection code).
  const auto   reference = ComputeReference<HUVolumeType>(volume, geometry, KernelEnum::Box, withTransform, 64);
  const auto   inverse = transform->GetInverseTransform();
  const auto   source = geometry->GetSourcePosition();
  const auto   normal = geometry->GetNormal();
  const double sid = 3000.0;
  double       expected = 0.0;
  for (itk::ImageRegionConstIteratorWithIndex<HUVolumeType> it(volume, volume->GetLargestPossibleRegion());
       !it.IsAtEnd();
       ++it)
  {
    const double mu = MuOfHU(it.Get());
    for (unsigned int q = 0; q < 64; ++q)
    {
      itk::ContinuousIndex<double, 3> index;
      index[0] = it.GetIndex()[0] - 0.375 + 0.25 * (q % 4);
      index[1] = it.GetIndex()[1] - 0.375 + 0.25 * (q / 4 % 4);
      index[2] = it.GetIndex()[2] - 0.375 + 0.25 * (q / 16);
      HUVolumeType::PointType inVolume;
      volume->TransformContinuousIndexToPhysicalPoint(index, inVolume);
      const auto   room = inverse->TransformPoint(inVolume);
      const auto   fromSource = room - source;
      const double z = -(fromSource * normal);
      const double lateral2 = fromSource.GetSquaredNorm() - z * z; // (u^2 + v^2) (z / SID)^2
      const double w = (sid / z) * (sid / z) * std::sqrt(sid * sid + lateral2 * (sid / z) * (sid / z)) / sid;
      expected += mu * w * (1.5 * 2.0 * 2.5) / 64.0;
    }
  }
  expected /= 4.0 * 4.0;
  EXPECT_NEAR(reference.Sum, expected, 2e-3 * expected) << "the exact image sum against a quadrature in the room";
}

TEST(PointBasedDRRExtremes, FloatHUBeyondTheScannersRangeMatchesExact)
{
  // Float CT (as NIfTI often is): -1e30 HU and the paddings are air; 3071, 32767 and 1e6 HU are dense metal.
  const float extremes[8] = { -1e30f, -32768.0f, -3024.0f, -2048.0f, -1024.0f, 3071.0f, 32767.0f, 1e6f };
  auto        volume = MakeCentredVolume<MuVolumeType>({ { 7, 6, 5 } }, Vec3(2.0, 2.0, 2.0), Identity<MuVolumeType>());
  auto *      buffer = volume->GetBufferPointer();
  for (size_t v = 0; v < 7 * 6 * 5; ++v)
  {
    buffer[v] = extremes[(v * 5 + v / 7) % 8];
  }
  auto         geometry = MakeGeometry(100.0, 150.0, 25.0, 16, 16, 1.5, 1.5);
  MatchOptions options;
  ExpectMatchesExact<MuVolumeType>(volume, geometry, nullptr, options, "float HU extremes");
  auto drr = PointBasedFilter<MuVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->Update();
  double mass = 0.0;
  for (size_t v = 0; v < 7 * 6 * 5; ++v)
  {
    mass += MuOfHU(buffer[v]) * 8.0;
  }
  EXPECT_NEAR(drr->GetTotalMass(), mass, 1e-6 * mass) << "mu of the extremes: natural, air clamped to zero";
}

TEST(PointBasedDRRExtremes, TwoToTheThirtyThreeSamplesStayCountedAndUnbiased)
{
  // 2^33 points (more than any 32-bit counter holds, 2^29 per stratum) on a parallel view along x whose 1.5 mm pixels
  // line up with the voxel columns, so that the exact reference is exact and every point lands with weight 1.
  auto volume = MakeCentredVolume<HUVolumeType>({ { 8, 8, 8 } }, Vec3(1.5, 1.5, 1.5), Identity<HUVolumeType>());
  FillPattern(volume, 12);
  auto       geometry = MakeGeometry(100.0, 150.0, 0.0, 12, 12, 1.5, 1.5, ProjectionEnum::Parallel);
  const auto reference = ComputeReference<HUVolumeType>(volume, geometry, KernelEnum::Box, nullptr, 2);

  constexpr uint64_t samples = uint64_t{ 1 } << 33;
  constexpr unsigned strata = 16;
  auto               drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetSampler(itk::DRRSamplerFactory::Create("stratified"));
  drr->SetNumberOfStrata(strata);
  drr->SetNumberOfSamples(samples);
  drr->SetSeed(33);
  drr->Update();
  EXPECT_EQ(drr->GetPointsOnDetector(), samples) << "every point lands; none lost to a 32-bit counter";

  const auto values = ToVector(drr->GetOutput());
  const auto errors = ToVector(drr->GetStandardErrorOutput());
  // Image sum * a = M (N / N): the fixed-point sums of 2^33 contributions lose nothing beyond float output rounding.
  const double sum = std::accumulate(values.begin(), values.end(), 0.0);
  EXPECT_NEAR(sum * 1.5 * 1.5, drr->GetTotalMass(), 1e-6 * drr->GetTotalMass());
  // Each pixel: a t-test of the estimate against the exact column integral with the filter's own standard error
  // (the spread of 16 independent strata: 15 degrees of freedom, P(|t| > 6) = 2.4e-5 per pixel), floored by the
  // float rounding of both images. The estimate is so precise here that a bias of 1e-6 would show.
  const double peak = *std::max_element(reference.Value.begin(), reference.Value.end());
  double       sumOfSquaredT = 0.0;
  size_t       signalPixels = 0;
  for (size_t p = 0; p < values.size(); ++p)
  {
    ASSERT_TRUE(std::isfinite(values[p]) && std::isfinite(errors[p])) << "pixel " << p;
    if (reference.Value[p] == 0.0)
    {
      // Outside the shadow. The voxel faces lie on pixel edges, and the single-precision projection places a point
      // within a float ulp of an edge (2^-24 of 6 mm, 1e-7 of a 1.5 mm pixel) on either side of it.
      EXPECT_LT(values[p], 1e-6 * peak) << "pixel " << p << " outside the volume's shadow";
      continue;
    }
    const double rounding = 2.0 * std::ldexp(reference.Value[p], -24);
    const double t = (values[p] - reference.Value[p]) / std::sqrt(errors[p] * errors[p] + rounding * rounding);
    EXPECT_LT(std::abs(t), 6.0) << "pixel " << p << ": " << values[p] << " vs exact " << reference.Value[p]
                                << " (standard error " << errors[p] << ")";
    EXPECT_LT(errors[p], 1e-5 * peak) << "pixel " << p << ": the test lost its power";
    sumOfSquaredT += t * t;
    ++signalPixels;
  }
  ASSERT_GT(signalPixels, 40u);
  // The spread matches the standard error: the mean of t^2 is 15 / 13 for 15 degrees of freedom (less where float
  // rounding dominates); far above, the errors are understated.
  EXPECT_LT(sumOfSquaredT / signalPixels, 3.0) << "the standard error understates the deviations";
}

// ---------------------------------------------------------------------------------------------------------------------
// Pipeline behaviour: progress, abort, caching, reproducibility.

template <typename TFilter>
std::vector<float>
RecordProgress(TFilter * filter)
{
  std::vector<float> progress;
  std::mutex         mutex;
  const auto         tag = filter->AddObserver(itk::ProgressEvent(), [&](const itk::EventObject &) {
    const std::lock_guard<std::mutex> lock(mutex);
    progress.push_back(filter->GetProgress());
  });
  filter->Update();
  filter->RemoveObserver(tag);
  return progress;
}

void
ExpectProgressWellFormed(const std::vector<float> & progress, const std::string & context)
{
  ASSERT_GE(progress.size(), 2u) << context;
  EXPECT_LT(progress.front(), 1.0f) << context;
  for (size_t i = 1; i < progress.size(); ++i)
  {
    EXPECT_GE(progress[i], progress[i - 1]) << context << ": progress went back at event " << i;
  }
  EXPECT_EQ(progress.back(), 1.0f) << context;
}

TEST(PointBasedDRRRobustness, ProgressIsNonDecreasingAndEndsAtOne)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 12, 12, 12 } }, Vec3(1.0, 1.0, 1.0), Identity<HUVolumeType>());
  FillPattern(volume);
  auto geometry = MakeGeometry(100.0, 150.0, 10.0, 16, 16, 1.5, 1.5);
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetNumberOfSamples(1000000); // 16 chunks
  ExpectProgressWellFormed(RecordProgress(drr.GetPointer()), "point-based");
  drr->SetSeed(1); // a second run reports its own progress from the start
  ExpectProgressWellFormed(RecordProgress(drr.GetPointer()), "point-based, second run");
  auto exact = ExactFilter<HUVolumeType>::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->SetRaysPerPixelSide(4);
  ExpectProgressWellFormed(RecordProgress(exact.GetPointer()), "exact");
}

template <typename TFilter>
void
ExpectAbortOnFirstProgress(TFilter * filter, const std::string & context)
{
  bool       aborted = false;
  bool       first = true;
  const auto progressTag = filter->AddObserver(itk::ProgressEvent(), [&](const itk::EventObject &) {
    if (first)
    {
      first = false;
      filter->AbortGenerateDataOn();
    }
  });
  const auto abortTag = filter->AddObserver(itk::AbortEvent(), [&](const itk::EventObject &) { aborted = true; });
  EXPECT_THROW(filter->Update(), itk::ProcessAborted) << context;
  EXPECT_TRUE(aborted) << context << ": no AbortEvent";
  filter->RemoveObserver(progressTag);
  filter->RemoveObserver(abortTag);
}

TEST(PointBasedDRRRobustness, AbortFromAProgressObserverStopsTheRender)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 16, 16, 16 } }, Vec3(1.0, 1.0, 1.0), Identity<HUVolumeType>());
  FillPattern(volume);
  auto geometry = MakeGeometry(100.0, 150.0, 10.0, 16, 16, 1.5, 1.5);
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetNumberOfSamples(10000000);
  ExpectAbortOnFirstProgress(drr.GetPointer(), "point-based, 10^7 samples");
  EXPECT_LT(drr->GetProgress(), 0.5f) << "the render ran on after the abort";
  // The filter is usable again afterwards.
  drr->AbortGenerateDataOff();
  drr->SetNumberOfSamples(20000);
  ASSERT_NO_THROW(drr->Update());
  const auto image = ToVector(drr->GetOutput());
  EXPECT_GT(std::accumulate(image.begin(), image.end(), 0.0), 0.0);

  auto exact = ExactFilter<HUVolumeType>::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->SetRaysPerPixelSide(64);
  ExpectAbortOnFirstProgress(exact.GetPointer(), "exact, 64 x 64 rays per pixel");
}

TEST(PointBasedDRRRobustness, CachedVolumeFollowsTransferFunctionAndInputChanges)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 10, 9, 8 } }, Vec3(1.5, 1.5, 1.5), Identity<HUVolumeType>());
  FillPattern(volume);
  auto geometry = MakeGeometry(100.0, 150.0, 40.0, 12, 12, 2.0, 2.0);
  auto drr = PointBasedFilter<HUVolumeType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetNumberOfSamples(100000);
  drr->SetSeed(3);
  drr->Update();
  const auto before = ToVector(drr->GetOutput());
  const auto beforeError = ToVector(drr->GetStandardErrorOutput());
  auto       exact = ExactFilter<HUVolumeType>::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->Update();
  const auto exactBefore = ToVector(exact->GetOutput());

  // Twice the water attenuation doubles every pixel of the same-seed render (same points, twice the mass).
  drr->GetTransferFunction()->SetMuWaterPerMillimeter(2.0 * muWater);
  drr->Update();
  exact->GetTransferFunction()->SetMuWaterPerMillimeter(2.0 * muWater);
  exact->Update();
  const auto after = ToVector(drr->GetOutput());
  const auto afterError = ToVector(drr->GetStandardErrorOutput());
  const auto exactAfter = ToVector(exact->GetOutput());
  ASSERT_GT(*std::max_element(before.begin(), before.end()), 0.0);
  for (size_t p = 0; p < before.size(); ++p)
  {
    EXPECT_FLOAT_EQ(after[p], 2.0 * before[p]) << "pixel " << p;
    EXPECT_FLOAT_EQ(afterError[p], 2.0 * beforeError[p]) << "pixel " << p;
    EXPECT_FLOAT_EQ(exactAfter[p], 2.0 * exactBefore[p]) << "pixel " << p;
  }

  // Changing the input in place and calling Modified() re-renders: the result is that of a fresh filter.
  FillBlock<HUVolumeType>(volume, { { 2, 2, 2 } }, { { 6, 5, 4 } }, 3000);
  volume->Modified();
  drr->Update();
  exact->Update();
  auto freshDRR = PointBasedFilter<HUVolumeType>::New();
  freshDRR->SetInput(volume);
  freshDRR->SetGeometry(geometry);
  freshDRR->SetNumberOfSamples(100000);
  freshDRR->SetSeed(3);
  freshDRR->GetTransferFunction()->SetMuWaterPerMillimeter(2.0 * muWater);
  freshDRR->Update();
  auto freshExact = ExactFilter<HUVolumeType>::New();
  freshExact->SetInput(volume);
  freshExact->SetGeometry(geometry);
  freshExact->GetTransferFunction()->SetMuWaterPerMillimeter(2.0 * muWater);
  freshExact->Update();
  const auto changed = ToVector(drr->GetOutput());
  EXPECT_NE(changed, after) << "the point-based output did not follow the input change";
  EXPECT_EQ(changed, ToVector(freshDRR->GetOutput()));
  EXPECT_NE(ToVector(exact->GetOutput()), exactAfter) << "the exact output did not follow the input change";
  EXPECT_EQ(ToVector(exact->GetOutput()), ToVector(freshExact->GetOutput()));
}

TEST(PointBasedDRRRobustness, SameSeedAndTransformGiveIdenticalBits)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 10, 9, 8 } }, Vec3(1.5, 1.5, 1.5), Identity<HUVolumeType>());
  FillPattern(volume, 9);
  auto affine = itk::AffineTransform<double, 3>::New();
  affine->Rotate3D(Vec3(0.0, 0.6, 0.8), 0.4);
  affine->Scale(Vec3(1.1, 0.95, 1.02));
  affine->Translate(Vec3(2.0, -3.0, 1.0));
  auto geometry = MakeGeometry(100.0, 150.0, 40.0, 12, 12, 2.0, 2.0);
  auto render = [&](unsigned int threads, uint64_t seed) {
    auto drr = PointBasedFilter<HUVolumeType>::New();
    drr->SetInput(volume);
    drr->SetGeometry(geometry);
    drr->SetTransform(affine);
    drr->SetNumberOfSamples(300000);
    drr->SetReconstructionKernel(KernelEnum::Tent);
    drr->SetSplat(SplatEnum::Bilinear);
    drr->SetSeed(seed);
    drr->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
    drr->SetNumberOfWorkUnits(threads);
    drr->Update();
    const size_t       pixels = drr->GetOutput()->GetBufferedRegion().GetNumberOfPixels();
    std::vector<float> bits(drr->GetOutput()->GetBufferPointer(), drr->GetOutput()->GetBufferPointer() + pixels);
    bits.insert(bits.end(),
                drr->GetStandardErrorOutput()->GetBufferPointer(),
                drr->GetStandardErrorOutput()->GetBufferPointer() + pixels);
    // Re-render with the same filter (forced by Modified()): the same bits again.
    drr->Modified();
    drr->Update();
    EXPECT_EQ(std::memcmp(bits.data(), drr->GetOutput()->GetBufferPointer(), pixels * sizeof(float)), 0)
      << "re-render of the same filter";
    EXPECT_EQ(
      std::memcmp(bits.data() + pixels, drr->GetStandardErrorOutput()->GetBufferPointer(), pixels * sizeof(float)), 0)
      << "re-render of the same filter, standard error";
    return bits;
  };
  const auto first = render(2, 11);
  const auto second = render(2, 11);
  const auto oneThread = render(1, 11);
  ASSERT_EQ(first.size(), second.size());
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(first.data(), oneThread.data(), first.size() * sizeof(float)), 0);
  EXPECT_NE(first, render(2, 12)) << "another seed must give another image";
}
// Preprocessing. The attenuation volume (levels of integer input, or mu per voxel) and the samplers' tables are built
// in parallel over fixed blocks of voxels: they must be the same bits on any number of threads, agree with the
// transfer function voxel by voxel, and reject bad input by naming the first bad voxel in memory order.

/** 128 x 96 x 48 voxels: 9 blocks of the preprocessing partition (2^16 voxels or more each). */
constexpr unsigned int blockyX = 128;
constexpr unsigned int blockyY = 96;
constexpr unsigned int blockyZ = 48;
constexpr uint64_t     blockyVoxels = uint64_t{ blockyX } * blockyY * blockyZ;

uint32_t
Hash(uint64_t v)
{
  uint64_t x = (v + 1) * 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return static_cast<uint32_t>(x ^ (x >> 31));
}

template <typename TVolume>
typename TVolume::Pointer
MakeBlockyVolume(const std::function<typename TVolume::PixelType(uint64_t)> & value)
{
  auto volume = MakeCentredVolume<TVolume>({ { blockyX, blockyY, blockyZ } }, Vec3(1.0, 1.0, 1.0), Identity<TVolume>());
  auto * buffer = volume->GetBufferPointer();
  for (uint64_t v = 0; v < blockyVoxels; ++v)
  {
    buffer[v] = value(v);
  }
  return volume;
}

/** A transfer function: a mode, or piecewise-linear points when given. */
struct Transfer
{
  TransferEnum                            Mode{ TransferEnum::Natural };
  itk::DRRTransferFunction::PointListType Points;
  void
  Apply(itk::DRRTransferFunction * transfer) const
  {
    transfer->SetMode(Mode);
    if (!Points.empty())
    {
      transfer->SetPiecewiseLinearPoints(Points);
    }
  }
};

/** The attenuation volume of an input, built on a number of threads. */
template <typename TVolume>
itk::DRRAttenuationVolume::ConstPointer
BuildOnThreads(const TVolume * input, unsigned int threads, const Transfer & mode)
{
  auto drr = PointBasedFilter<TVolume>::New();
  drr->SetInput(input);
  mode.Apply(drr->GetTransferFunction());
  drr->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
  drr->SetNumberOfWorkUnits(threads);
  return drr->GetAttenuationVolume();
}

void
ExpectSameVolume(const itk::DRRAttenuationVolume & a, const itk::DRRAttenuationVolume & b, const std::string & context)
{
  ASSERT_EQ(a.HasLevels(), b.HasLevels()) << context;
  ASSERT_EQ(a.GetNumberOfLevels(), b.GetNumberOfLevels()) << context;
  if (a.HasLevels())
  {
    for (size_t l = 0; l < a.GetNumberOfLevels(); ++l)
    {
      ASSERT_EQ(a.GetLevelStart(l), b.GetLevelStart(l)) << context << ", level " << l;
      ASSERT_EQ(a.GetLevelMu(l), b.GetLevelMu(l)) << context << ", level " << l;
    }
    const uint64_t listed = a.GetLevelStart(a.GetNumberOfLevels());
    ASSERT_EQ(listed, b.GetLevelStart(b.GetNumberOfLevels())) << context;
    EXPECT_EQ(std::memcmp(a.GetLevelVoxels(), b.GetLevelVoxels(), listed * sizeof(uint32_t)), 0) << context;
  }
  EXPECT_EQ(std::memcmp(a.GetMuBuffer(), b.GetMuBuffer(), a.GetNumberOfVoxels() * sizeof(float)), 0) << context;
  const double massA = a.ComputeTotalMass();
  const double massB = b.ComputeTotalMass();
  EXPECT_EQ(std::memcmp(&massA, &massB, sizeof(double)), 0) << context << ": " << massA << " vs " << massB;
  EXPECT_EQ(a.ComputeMaximumMu(), b.ComputeMaximumMu()) << context;
  EXPECT_EQ(a.GetSmallestPositiveMu(), b.GetSmallestPositiveMu()) << context;
}

/** mu is the transfer function of every voxel, to the bit; the levels list exactly the voxels of mu > 0, each level
 * in increasing voxel order and of one mu. */
template <typename TVolume>
void
ExpectVolumeMatchesTransfer(const TVolume *                   input,
                            const itk::DRRAttenuationVolume & volume,
                            const Transfer &                  mode,
                            const std::string &               context)
{
  auto transfer = itk::DRRTransferFunction::New();
  mode.Apply(transfer);
  const auto *  values = input->GetBufferPointer();
  const float * mu = volume.GetMuBuffer();
  uint64_t      mismatches = 0;
  uint64_t      nonAir = 0;
  float         largest = 0.0f;
  float         smallest = std::numeric_limits<float>::max();
  for (uint64_t v = 0; v < volume.GetNumberOfVoxels(); ++v)
  {
    const float expected = static_cast<float>(transfer->Evaluate(static_cast<double>(values[v])));
    if (mismatches == 0 && mu[v] != expected)
    {
      ADD_FAILURE() << context << ": voxel " << v << " value " << values[v] << " has mu " << mu[v] << ", expected "
                    << expected;
    }
    mismatches += mu[v] != expected ? 1 : 0;
    nonAir += mu[v] > 0.0f ? 1 : 0;
    largest = std::max(largest, mu[v]);
    smallest = mu[v] > 0.0f ? std::min(smallest, mu[v]) : smallest;
  }
  EXPECT_EQ(mismatches, 0u) << context;
  EXPECT_EQ(volume.ComputeMaximumMu(), largest) << context;
  EXPECT_EQ(volume.GetSmallestPositiveMu(), nonAir > 0 ? smallest : 0.0f) << context;
  if (!volume.HasLevels())
  {
    return;
  }
  ASSERT_EQ(volume.GetLevelStart(volume.GetNumberOfLevels()), nonAir) << context;
  const uint32_t * voxels = volume.GetLevelVoxels();
  uint64_t         wrong = 0;
  for (size_t l = 0; l < volume.GetNumberOfLevels(); ++l)
  {
    EXPECT_GT(volume.GetLevelMu(l), 0.0f) << context;
    for (uint64_t i = volume.GetLevelStart(l); i < volume.GetLevelStart(l + 1); ++i)
    {
      wrong += mu[voxels[i]] != volume.GetLevelMu(l) ? 1 : 0;
      wrong += i > volume.GetLevelStart(l) && voxels[i] <= voxels[i - 1] ? 1 : 0;
    }
  }
  EXPECT_EQ(wrong, 0u) << context << ": voxels listed in the wrong level or out of order";
}

/** A batch of a sampler's draws (voxels and weights), with its mass and table size, as bits. */
std::vector<double>
SamplerFingerprint(const std::string & name, const itk::DRRAttenuationVolume & volume)
{
  auto sampler = itk::DRRSamplerFactory::Create(name);
  sampler->Initialize(volume);
  constexpr uint64_t                count = 4096;
  std::vector<uint64_t>             voxels(count);
  std::vector<double>               weights(count);
  itk::DRRPointSampler::SampleRange range;
  range.Seed = 5;
  range.Count = count;
  range.StratumSize = count;
  itk::detail::DRRPhiloxRandom random(5, 0, 0);
  sampler->GenerateBatch(random, range, voxels.data(), weights.data());
  std::vector<double> fingerprint(weights);
  fingerprint.insert(fingerprint.end(), voxels.begin(), voxels.end());
  fingerprint.push_back(sampler->GetTotalMass());
  fingerprint.push_back(sampler->GetMaximumWeight());
  fingerprint.push_back(static_cast<double>(sampler->GetTableSizeInBytes()));
  return fingerprint;
}

template <typename TVolume>
void
ExpectReproduciblePreprocessing(const TVolume * input, const Transfer & mode, bool levels, const std::string & context)
{
  const auto reference = BuildOnThreads(input, 1, mode);
  EXPECT_EQ(reference->HasLevels(), levels) << context;
  ExpectVolumeMatchesTransfer(input, *reference, mode, context);
  for (unsigned int threads : { 2u, 3u, 5u })
  {
    ExpectSameVolume(
      *reference, *BuildOnThreads(input, threads, mode), context + ", " + std::to_string(threads) + " threads");
  }
  // The samplers build their tables on ITK's default threads: vary them.
  const auto defaultThreads = itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
  for (const std::string name : { "level-alias", "paper-hybrid", "metropolis", "mcvr" })
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(1);
    const auto one = SamplerFingerprint(name, *BuildOnThreads(input, 1, mode));
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(3);
    const auto three = SamplerFingerprint(name, *BuildOnThreads(input, 3, mode));
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(defaultThreads);
    ASSERT_EQ(one.size(), three.size());
    EXPECT_EQ(std::memcmp(one.data(), three.data(), one.size() * sizeof(double)), 0) << context << ", " << name;
  }
}

TEST(PointBasedDRRPreprocessing, SameBitsOnAnyThreadsAndMuOfEveryVoxelFromTheTransferFunction)
{
  // CT in HU, air and padding included, as short and as integer-valued float: the same levels.
  const auto hu = [](uint64_t v) { return static_cast<short>(static_cast<int>(Hash(v) % 3300) - 1100); };
  const auto shortCT = MakeBlockyVolume<HUVolumeType>(hu);
  const auto floatCT = MakeBlockyVolume<MuVolumeType>([&](uint64_t v) { return static_cast<float>(hu(v)); });
  ExpectReproduciblePreprocessing(shortCT.GetPointer(), Transfer{}, true, "short HU");
  ExpectReproduciblePreprocessing(floatCT.GetPointer(), Transfer{}, true, "integer float HU");
  ExpectSameVolume(*BuildOnThreads(shortCT.GetPointer(), 2, Transfer{}),
                   *BuildOnThreads(floatCT.GetPointer(), 2, Transfer{}),
                   "short and float HU");

  // A piecewise-linear transfer function whose mu falls, then rises: the smallest mu is not the lowest value's.
  ExpectReproduciblePreprocessing(
    shortCT.GetPointer(),
    Transfer{ TransferEnum::PiecewiseLinear, { { -1100.0, 0.05 }, { 0.0, 0.001 }, { 2200.0, 0.02 } } },
    true,
    "short HU, falling and rising mu");

  // Beyond int16 but spanning less than 2^16: levels from the smallest value.
  using IntVolumeType = itk::Image<int, 3>;
  const auto wide =
    MakeBlockyVolume<IntVolumeType>([](uint64_t v) { return 40000 + static_cast<int>(Hash(v) % 20000); });
  ExpectReproduciblePreprocessing(wide.GetPointer(), Transfer{}, true, "int beyond int16");
  // One below int16 at the smallest: not keyed from -32768 (that key would be -1), but from the smallest value (a
  // transfer function that makes them tissue).
  const auto below =
    MakeBlockyVolume<IntVolumeType>([](uint64_t v) { return -32769 + static_cast<int>(Hash(v) % 3000); });
  ExpectReproduciblePreprocessing(below.GetPointer(),
                                  Transfer{ TransferEnum::PiecewiseLinear, { { -32769.0, 0.01 }, { -29770.0, 0.03 } } },
                                  true,
                                  "int from one below int16");

  // Spanning more than 2^16, or not integers (a fraction of 1/1024 on one voxel is enough): mu per voxel, binned by
  // the level samplers.
  const auto wider =
    MakeBlockyVolume<IntVolumeType>([](uint64_t v) { return static_cast<int>(Hash(v) % 100000) - 1000; });
  ExpectReproduciblePreprocessing(wider.GetPointer(), Transfer{}, false, "int spanning 100000");
  const auto almost = MakeBlockyVolume<MuVolumeType>(
    [&](uint64_t v) { return static_cast<float>(hu(v)) + (v == blockyVoxels - 7 ? 1.0f / 1024.0f : 0.0f); });
  ExpectReproduciblePreprocessing(almost.GetPointer(), Transfer{}, false, "float HU with one fraction");
  const auto mu = MakeBlockyVolume<MuVolumeType>(
    [](uint64_t v) { return Hash(v) % 5 == 0 ? 0.0f : static_cast<float>(Hash(v) % 100000) * 1e-6f; });
  ExpectReproduciblePreprocessing(mu.GetPointer(), Transfer{ TransferEnum::Identity, {} }, false, "mu");
}

TEST(PointBasedDRRPreprocessing, LevelTablesTakeFourBytesPerNonAirVoxel)
{
  const auto ct = MakeBlockyVolume<HUVolumeType>(
    [](uint64_t v) { return static_cast<short>(static_cast<int>(Hash(v) % 3300) - 1100); });
  const auto volume = BuildOnThreads(ct.GetPointer(), 2, Transfer{});
  const auto nonAir = static_cast<double>(volume->GetLevelStart(volume->GetNumberOfLevels()));
  for (const std::string name : { "level-alias", "paper-hybrid", "metropolis" })
  {
    auto sampler = itk::DRRSamplerFactory::Create(name);
    sampler->Initialize(*volume);
    const double perVoxel = static_cast<double>(sampler->GetTableSizeInBytes()) / nonAir;
    EXPECT_GE(perVoxel, 4.0) << name;
    // 4 bytes of voxel index, plus per level tables spread over the voxels.
    EXPECT_LE(perVoxel, 4.0 + 64.0 * static_cast<double>(volume->GetNumberOfLevels()) / nonAir) << name;
  }
}

TEST(PointBasedDRRPreprocessing, BadVoxelsInSeveralBlocksNameTheFirstInMemoryOrder)
{
  // Two bad voxels, blocks apart: whatever the threads, the one first in memory order is named.
  const itk::Index<3> first = { { 5, 40, 30 } };
  const itk::Index<3> second = { { 100, 10, 41 } };
  for (unsigned int threads : { 1u, 2u, 4u })
  {
    // Integer input with the identity transfer function: negative values are negative mu.
    auto ct = MakeBlockyVolume<HUVolumeType>([](uint64_t v) { return static_cast<short>(Hash(v) % 7); });
    ct->SetPixel(second, -3);
    ct->SetPixel(first, -7);
    auto drr = PointBasedFilter<HUVolumeType>::New();
    drr->SetInput(ct);
    drr->GetTransferFunction()->SetMode(TransferEnum::Identity);
    drr->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
    drr->SetNumberOfWorkUnits(threads);
    ExpectUpdateThrows(drr.GetPointer(), { "negative", "-7", "voxel (5, 40, 30)" }, "negative integer input");

    // Float input: a non-finite voxel, then a negative one.
    auto mu =
      MakeBlockyVolume<MuVolumeType>([](uint64_t v) { return 0.01f + 1e-6f * static_cast<float>(Hash(v) % 7); });
    mu->SetPixel(second, -0.5f);
    mu->SetPixel(first, -std::numeric_limits<float>::infinity());
    auto drrMu = PointBasedFilter<MuVolumeType>::New();
    drrMu->SetInput(mu);
    drrMu->GetTransferFunction()->SetMode(TransferEnum::Identity);
    drrMu->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
    drrMu->SetNumberOfWorkUnits(threads);
    ExpectUpdateThrows(drrMu.GetPointer(), { "non-finite", "voxel (5, 40, 30)" }, "infinite float input");
    mu->SetPixel(first, 0.01f);
    mu->SetPixel(second, std::numeric_limits<float>::quiet_NaN());
    mu->SetPixel({ { 0, 0, 47 } }, -0.25f);
    ExpectUpdateThrows(drrMu.GetPointer(), { "non-finite", "voxel (100, 10, 41)" }, "NaN before a negative voxel");
  }
}
} // namespace

// A cut file read by an itk::ImageFileReader into the filters: refused by the filters' own check before anything is
// read, whole or slab by slab (NumberOfStreamDivisions), for the formats whose readers do not say so themselves (NIfTI
// fills the missing voxels with zeros; MetaImage, streamed, says so on std::cerr only). The reader's file, once whole
// again, renders.
TEST(PointBasedDRRRobustness, ACutFileUpstreamIsRefusedWholeAndStreamed)
{
  auto volume = MakeCentredVolume<HUVolumeType>({ { 12, 10, 16 } }, Vec3(1.0, 1.0, 1.0), Identity<HUVolumeType>());
  FillPattern(volume);
  const std::string directory = ::testing::TempDir();
  for (const std::string name : { "upstream_cut.nii", "upstream_cut.mha" })
  {
    const std::string path = directory + "/" + std::to_string(::getpid()) + name;
    itk::WriteImage(volume, path);
    std::string bytes;
    {
      std::ifstream in(path, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    for (const unsigned divisions : { 1u, 4u })
    {
      for (const bool exact : { false, true })
      {
        const std::string context =
          name + (exact ? ", exact" : ", points") + ", " + std::to_string(divisions) + " slabs";
        {
          std::ofstream out(path, std::ios::binary | std::ios::trunc);
          out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() * 2 / 3));
        }
        auto reader = itk::ImageFileReader<HUVolumeType>::New();
        reader->SetFileName(path);
        FilterBase<HUVolumeType>::Pointer filter;
        if (exact)
        {
          auto drr = ExactFilter<HUVolumeType>::New();
          drr->SetNumberOfStreamDivisions(divisions);
          filter = drr;
        }
        else
        {
          auto drr = PointBasedFilter<HUVolumeType>::New();
          drr->SetNumberOfSamples(20000);
          drr->SetNumberOfStreamDivisions(divisions);
          filter = drr;
        }
        filter->SetInput(reader->GetOutput());
        filter->SetGeometry(MakeGeometry(100.0, 150.0, 0.0, 8, 8, 2.0, 2.0));
        ExpectUpdateThrows(filter.GetPointer(), { "cannot read", name, "truncated" }, context);
        {
          std::ofstream out(path, std::ios::binary | std::ios::trunc);
          out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        }
        reader->Modified();
        EXPECT_NO_THROW(filter->Update()) << context << ", the file whole again";
      }
    }
  }
}
