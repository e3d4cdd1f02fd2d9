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
// PointBasedDRRMetricv4: its analytic derivative against central differences of the same kept points (every beam,
// both similarities, Euler and versor poses), the backward pass against the render it differentiates, the same bits on
// any number of threads, ITK's v4 optimizers recovering a known pose with it, and the input it refuses.
#include "itkPointBasedDRRMetricv4.h"
#include "itkBSplineTransform.h"
#include "itkConjugateGradientLineSearchOptimizerv4.h"
#include "itkDRRImageSimilarity.h"
#include "itkDRRPointPoseGradient.h"
#include "itkDRRSamplerFactory.h"
#include "itkEuler3DTransform.h"
#include "itkExactDRRImageFilter.h"
#include "itkLBFGSBOptimizerv4.h"
#include "itkPointBasedDRRParameterScalesEstimator.h"
#include "itkQuasiNewtonOptimizerv4.h"
#include "itkRegularStepGradientDescentOptimizerv4.h"
#include "itkTranslationTransform.h"
#include "itkVersorRigid3DTransform.h"
#include "PointBasedDRRTestHelpers.h"
#include "gtest/gtest.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <random>
#include <string>
#include <vector>

namespace
{
using VolumeType = itk::Image<float, 3>;
using MetricType = itk::PointBasedDRRMetricv4<VolumeType>;
using XRayType = MetricType::XRayImageType;
using GeometryType = itk::DRRProjectionGeometry;
using EulerType = itk::Euler3DTransform<double>;
using VersorType = itk::VersorRigid3DTransform<double>;
using ProjectionEnum = itk::PointBasedDRREnums::Projection;
using SimilarityEnum = itk::PointBasedDRREnums::Similarity;

/** The registration tests' CT (PointBasedDRRTestHelpers.h). */
VolumeType::Pointer
MakePhantom()
{
  return PointBasedDRRTest::MakeAsymmetricPhantom();
}

/** A view about the room origin (the phantom's centre), 48 x 40 pixels of 3 mm at the isocenter. A close source (SAD
 * 200, SID 400 mm: depths across the phantom from 150 to 250 mm) makes the perspective weight change a lot with depth,
 * so that its derivative is a large part of the rotations'. */
GeometryType::Pointer
View(double gantryInDegrees, ProjectionEnum projection)
{
  auto geometry = GeometryType::New();
  geometry->SetProjection(projection);
  geometry->SetGantryAngleInDegrees(gantryInDegrees);
  geometry->SetSourceToIsocenterDistance(200.0);
  geometry->SetSourceToDetectorDistance(400.0);
  geometry->SetDetectorSize({ { 48, 40 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(projection == ProjectionEnum::Parallel ? 3.0 : 6.0));
  return geometry;
}

/** The "X-ray": the exact DRR (2 x 2 rays per pixel) of the phantom with the room-to-CT transform truth. */
XRayType::Pointer
RenderXRay(const VolumeType * volume, GeometryType * geometry, const itk::Transform<double, 3, 3> * truth)
{
  auto filter = itk::ExactDRRImageFilter<VolumeType, XRayType>::New();
  filter->SetInput(volume);
  filter->SetGeometry(geometry);
  filter->SetTransform(truth);
  filter->SetRaysPerPixelSide(2);
  filter->Update();
  XRayType::Pointer image = filter->GetOutput();
  image->DisconnectPipeline();
  return image;
}

/** An Euler pose about the phantom's centre: rx ry rz (radians), tx ty tz (mm). */
EulerType::Pointer
EulerPose(const VolumeType * volume, const std::vector<double> & parameters)
{
  auto pose = EulerType::New();
  pose->SetCenter(GeometryType::ComputeImageCenter(volume));
  EulerType::ParametersType p(6);
  for (unsigned int k = 0; k < 6; ++k)
  {
    p[k] = parameters[k];
  }
  pose->SetParameters(p);
  return pose;
}

/** A metric on the phantom with X-rays at the identity, seen from the gantries, at the pose. */
MetricType::Pointer
MakeMetric(const VolumeType *             volume,
           ProjectionEnum                 projection,
           const std::vector<double> &    gantries,
           itk::Transform<double, 3, 3> * pose,
           SimilarityEnum                 similarity,
           uint64_t                       samples)
{
  auto metric = MetricType::New();
  metric->SetVolume(volume);
  const auto identity = EulerPose(volume, { 0, 0, 0, 0, 0, 0 });
  for (const double gantry : gantries)
  {
    const auto geometry = View(gantry, projection);
    metric->AddXRay(RenderXRay(volume, geometry, identity), geometry);
  }
  metric->SetMovingTransform(pose);
  metric->SetSimilarity(similarity);
  metric->SetNumberOfSamples(samples);
  metric->Initialize();
  return metric;
}

/** The central difference of the metric's value along parameter j with step h (the parameters restored after). */
double
CentralDifference(MetricType * metric, unsigned int j, double h)
{
  const MetricType::ParametersType start = metric->GetParameters();
  MetricType::ParametersType       p = start;
  p[j] = start[j] + h;
  metric->SetParameters(p);
  const double forward = metric->GetValue();
  p[j] = start[j] - h;
  metric->SetParameters(p);
  const double backward = metric->GetValue();
  p = start;
  metric->SetParameters(p);
  return (forward - backward) / (2.0 * h);
}

/** Checks the metric's derivative at its current pose against central differences, component by component.
 *
 * The bound. For a function three times differentiable on the step, FD_h - V' = h^2 V''' / 6 + O(h^4), and
 * FD_2h - FD_h = 3 h^2 V''' / 6 + O(h^4): the truncation is (FD_2h - FD_h) / 3 (Richardson), which the bound counts
 * twice (2 |FD_2h - FD_h| / 3, at least). The value is smooth except where a point's bilinear splat crosses a pixel
 * centre line (a kink: its term of V' jumps) and for the single-precision positions of the render (a column rounded by
 * about 2^-24 of itself, 1e-5 pixel here); the steps (0.05 mm, 1 mrad or a versor's 5e-4: every point moves by 0.02
 * pixel or less) make both small and of random sign, and they are bounded by a floor of 0.3% of the derivative's norm
 * in mm (each component scaled by the mean displacement one unit of its parameter gives the CT's corners,
 * ComputeParameterScales(): a rotation's derivative per radian is worth its RMS lever arm in mm). Measured: the
 * differences are 2.5 to 100 times below the bound.
 *
 * The mutations it catches (docs/registration.md, "The metric's tests"): the perspective weight's derivative dropped
 * (the rotations of a close cone change by 5 to 50%), one column of the transform's Jacobian dropped (a component
 * becomes 0), the v4 sign flipped (every component changes sign). */
void
ExpectDerivativeIsTheCentralDifference(MetricType *          metric,
                                       double                translationStep,
                                       double                rotationStep,
                                       const std::string &   what,
                                       std::vector<double> & visibility)
{
  MetricType::MeasureType    value;
  MetricType::DerivativeType derivative;
  metric->GetValueAndDerivative(value, derivative);
  ASSERT_TRUE(std::isfinite(value)) << what;
  const MetricType::ScalesType scales = metric->ComputeParameterScales();
  const unsigned int           count = metric->GetNumberOfParameters();
  visibility.resize(count, 0.0);
  double normInMillimetres = 0.0;
  for (unsigned int j = 0; j < count; ++j)
  {
    normInMillimetres += derivative[j] * derivative[j] / scales[j];
  }
  normInMillimetres = std::sqrt(normInMillimetres);
  ASSERT_GT(normInMillimetres, 0.0) << what;
  for (unsigned int j = 0; j < count; ++j)
  {
    const double h = scales[j] > 4.0 ? rotationStep : translationStep; // a rotation's unit moves the corners far
    const double fd = CentralDifference(metric, j, h);
    const double fd2 = CentralDifference(metric, j, 2.0 * h);
    const double analytic = -derivative[j]; // v4: the derivative returned is minus the value's
    const double bound = 2.0 * std::abs(fd2 - fd) / 3.0 + 0.0015 * normInMillimetres * std::sqrt(scales[j]);
    EXPECT_NEAR(analytic, fd, bound) << what << ", parameter " << j << ": FD(2h) " << fd2 << ", |A| in mm "
                                     << normInMillimetres;
    visibility[j] = std::max(visibility[j], std::abs(analytic) / bound);
  }
}

/** A component smaller than its bound could be dropped (its Jacobian column lost) unseen: every parameter must be at
 * least twice its bound in one of the cases checked. */
void
ExpectEveryParameterVisible(const std::vector<double> & visibility)
{
  for (size_t j = 0; j < visibility.size(); ++j)
  {
    EXPECT_GT(visibility[j], 2.0) << "parameter " << j << " is never large enough to be checked";
  }
}
} // namespace

TEST(PointBasedDRRMetricv4, DerivativeIsTheCentralDifferenceOfTheSameKeptPoints)
{
  const auto volume = MakePhantom();
  struct Case
  {
    ProjectionEnum      Projection;
    std::vector<double> Gantries;
    SimilarityEnum      Similarity;
    std::vector<double> Pose;
  };
  const std::vector<Case> cases{
    { ProjectionEnum::Perspective, { 90, 0 }, SimilarityEnum::GradientCorrelation, { 0.03, -0.02, 0.04, 2, -1.5, 1 } },
    { ProjectionEnum::Perspective,
      { 90, 0 },
      SimilarityEnum::NormalizedCorrelation,
      { -0.05, 0.04, 0.03, -3, 2, 2.5 } },
    { ProjectionEnum::Localizer, { 0 }, SimilarityEnum::GradientCorrelation, { 0.04, 0.05, -0.03, 1.5, 2, -2 } },
    { ProjectionEnum::Parallel, { 30, 120 }, SimilarityEnum::NormalizedCorrelation, { 0.05, -0.04, 0.06, 2, 3, -1 } },
  };
  std::vector<double> visibility;
  for (const Case & c : cases)
  {
    auto               pose = EulerPose(volume, c.Pose);
    auto               metric = MakeMetric(volume, c.Projection, c.Gantries, pose, c.Similarity, 1000000);
    std::ostringstream what;
    what << c.Projection << " " << c.Similarity << " Euler";
    ExpectDerivativeIsTheCentralDifference(metric, 0.05, 1e-3, what.str(), visibility);
  }
  ExpectEveryParameterVisible(visibility);
}

TEST(PointBasedDRRMetricv4, DerivativeOfAVersorPoseIsTheCentralDifference)
{
  const auto volume = MakePhantom();
  auto       pose = VersorType::New();
  pose->SetCenter(GeometryType::ComputeImageCenter(volume));
  VersorType::ParametersType p(6);
  const double               parameters[6] = { 0.02, -0.03, 0.025, -2, 1.5, 2 }; // versor's right part, then mm
  for (unsigned int k = 0; k < 6; ++k)
  {
    p[k] = parameters[k];
  }
  pose->SetParameters(p);
  auto metric =
    MakeMetric(volume, ProjectionEnum::Perspective, { 90, 0 }, pose, SimilarityEnum::GradientCorrelation, 1000000);
  std::vector<double> visibility;
  ExpectDerivativeIsTheCentralDifference(metric, 0.05, 5e-4, "perspective GradientCorrelation Versor", visibility);
  ExpectEveryParameterVisible(visibility);
}

TEST(PointBasedDRRMetricv4, BackwardPassReadsTheWeightsWhereTheRenderSplats)
{
  // Phi = sum_k G_k D_k from the render, and from the points in the backward pass: the same points, the same bilinear
  // shares, for any image G (here random); equal up to the render's rounding (float contributions, fixed point).
  const auto volume = MakePhantom();
  auto       stage = itk::DRRImageToAttenuationVolumeFilter<VolumeType>::New();
  stage->SetInput(volume);
  stage->Update();
  const itk::DRRAttenuationVolume * model = stage->GetOutput();
  auto                              sampler = itk::DRRSamplerFactory::Create("stratified");
  sampler->Initialize(*model);
  itk::DRRPointRenderer::Settings settings;
  settings.NumberOfSamples = 200000;
  settings.Splat = itk::PointBasedDRREnums::Splat::Bilinear;
  auto       threader = itk::MultiThreaderBase::New();
  const auto cloud = itk::DRRPointRenderer::Draw(*model, *sampler, settings, threader, nullptr);
  for (const ProjectionEnum projection :
       { ProjectionEnum::Perspective, ProjectionEnum::Localizer, ProjectionEnum::Parallel })
  {
    const auto                          pose = EulerPose(volume, { 0.1, -0.2, 0.15, 5, -4, 3 });
    itk::DRRPointProjection::MatrixType matrix = pose->GetMatrix();
    itk::DRRPointProjection::VectorType offset = pose->GetOffset();
    const auto                          geometry = View(30, projection);
    itk::DRRPointProjection             projector(*geometry, *model, matrix, offset);
    const auto   result = itk::DRRPointRenderer::Render(*cloud, projector, settings, threader, nullptr);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<double>                    weights(result.LineIntegral.size());
    double                                 phi = 0.0, scale = 0.0;
    for (size_t k = 0; k < weights.size(); ++k)
    {
      weights[k] = uniform(random);
      phi += weights[k] * result.LineIntegral[k];
      scale += std::abs(weights[k] * result.LineIntegral[k]);
    }
    projector.SetMinimumDepth(result.MinimumDepth);
    const auto moments = itk::DRRPointPoseGradient::Compute(
      *cloud, projector, itk::PointBasedDRREnums::PointWeighting::Unbiased, weights.data(), threader);
    EXPECT_NEAR(moments.Value, phi, 1e-6 * scale) << projection;
    EXPECT_GT(moments.PointsOnDetector, cloud->GetNumberOfPoints() / 2) << projection;
  }
}

TEST(PointBasedDRRMetricv4, SameBitsOnAnyNumberOfThreads)
{
  const auto                 volume = MakePhantom();
  MetricType::DerivativeType derivatives[2];
  double                     values[2];
  const unsigned int         threads[2] = { 1, 3 };
  for (unsigned int run = 0; run < 2; ++run)
  {
    auto pose = EulerPose(volume, { 0.03, -0.02, 0.04, 2, -1.5, 1 });
    auto metric = MetricType::New();
    metric->SetNumberOfWorkUnits(threads[run]);
    metric->SetVolume(volume);
    const auto identity = EulerPose(volume, { 0, 0, 0, 0, 0, 0 });
    for (const double gantry : { 90.0, 0.0 })
    {
      const auto geometry = View(gantry, ProjectionEnum::Perspective);
      metric->AddXRay(RenderXRay(volume, geometry, identity), geometry);
    }
    metric->SetMovingTransform(pose);
    metric->SetNumberOfSamples(300000);
    metric->SetDetectorShrinkFactor(2);
    metric->SetSmoothingSigma(5.0);
    metric->Initialize();
    metric->GetValueAndDerivative(values[run], derivatives[run]);
  }
  EXPECT_EQ(values[0], values[1]);
  for (unsigned int j = 0; j < 6; ++j)
  {
    EXPECT_EQ(derivatives[0][j], derivatives[1][j]) << j;
  }
}

TEST(PointBasedDRRMetricv4, SmoothedAndBinnedDerivativeIsTheCentralDifference)
{
  // The smoothing goes back through its own adjoint and the binning through the binned view.
  const auto volume = MakePhantom();
  auto       pose = EulerPose(volume, { -0.03, 0.04, 0.02, 1, 2, -2 });
  auto       metric = MetricType::New();
  metric->SetVolume(volume);
  const auto identity = EulerPose(volume, { 0, 0, 0, 0, 0, 0 });
  for (const double gantry : { 90.0, 0.0 })
  {
    const auto geometry = View(gantry, ProjectionEnum::Perspective);
    metric->AddXRay(RenderXRay(volume, geometry, identity), geometry);
  }
  metric->SetMovingTransform(pose);
  metric->SetNumberOfSamples(1000000);
  metric->SetDetectorShrinkFactor(2);
  metric->SetSmoothingSigma(8.0);
  metric->Initialize();
  std::vector<double> visibility;
  ExpectDerivativeIsTheCentralDifference(metric, 0.05, 1e-3, "binned 2 x 2, smoothed 8 mm", visibility);
  ExpectEveryParameterVisible(visibility);
}

namespace
{
/** Initialize() throws an itk::ExceptionObject whose description contains what. */
void
ExpectInitializeRefused(MetricType * metric, const std::string & what)
{
  try
  {
    metric->Initialize();
    ADD_FAILURE() << "no exception; expected one about '" << what << "'";
  }
  catch (const itk::ExceptionObject & error)
  {
    EXPECT_NE(std::string(error.GetDescription()).find(what), std::string::npos) << error.GetDescription();
  }
}

/** A metric of the phantom with one AP X-ray at the identity, not yet initialized. */
MetricType::Pointer
MakeUninitializedMetric(const VolumeType * volume, const XRayType * xray, const GeometryType * geometry)
{
  auto metric = MetricType::New();
  metric->SetVolume(volume);
  metric->AddXRay(xray, geometry);
  metric->SetNumberOfSamples(100000);
  return metric;
}
} // namespace

TEST(PointBasedDRRMetricv4, RefusesInputItCannotUse)
{
  const auto volume = MakePhantom();
  const auto geometry = View(90, ProjectionEnum::Perspective);
  const auto identity = EulerPose(volume, { 0, 0, 0, 0, 0, 0 });
  const auto xray = RenderXRay(volume, geometry, identity);

  ExpectInitializeRefused(MetricType::New(), "no CT");

  auto noXRay = MetricType::New();
  noXRay->SetVolume(volume);
  ExpectInitializeRefused(noXRay, "no X-ray");

  auto air = VolumeType::New();
  air->CopyInformation(volume);
  air->SetRegions(volume->GetLargestPossibleRegion());
  air->Allocate();
  air->FillBuffer(-1000.0f);
  ExpectInitializeRefused(MakeUninitializedMetric(air, xray, geometry), "all air");

  auto nanCopy = XRayType::New();
  nanCopy->CopyInformation(xray);
  nanCopy->SetRegions(xray->GetLargestPossibleRegion());
  nanCopy->Allocate();
  std::copy(xray->GetBufferPointer(), xray->GetBufferPointer() + 48 * 40, nanCopy->GetBufferPointer());
  nanCopy->GetBufferPointer()[100] = std::numeric_limits<float>::quiet_NaN();
  ExpectInitializeRefused(MakeUninitializedMetric(volume, nanCopy, geometry), "not a finite number (pixel 100");

  auto flat = XRayType::New();
  flat->CopyInformation(xray);
  flat->SetRegions(xray->GetLargestPossibleRegion());
  flat->Allocate();
  flat->FillBuffer(3.0f);
  ExpectInitializeRefused(MakeUninitializedMetric(volume, flat, geometry), "constant (3)");

  auto                    away = View(90, ProjectionEnum::Perspective);
  GeometryType::PointType farAway;
  farAway[0] = 2000.0;
  farAway[1] = 0.0;
  farAway[2] = 0.0;
  away->SetIsocenter(farAway);
  ExpectInitializeRefused(MakeUninitializedMetric(volume, xray, away), "misses the volume");

  // A view that sees the volume, whose field a smoothing far wider than it erodes away: the smoothing is named.
  auto wide = MakeUninitializedMetric(volume, xray, geometry);
  wide->SetSmoothingSigma(1000.0);
  ExpectInitializeRefused(wide, "is eroded away by the smoothing of 1000 mm");

  auto otherSize = View(90, ProjectionEnum::Perspective);
  otherSize->SetDetectorSize({ { 40, 40 } });
  ExpectInitializeRefused(MakeUninitializedMetric(volume, xray, otherSize), "48 x 40 pixels, its view 40 x 40");

  auto noGeometry = MakeUninitializedMetric(volume, xray, nullptr);
  ExpectInitializeRefused(noGeometry, "no image or no geometry");

  auto zero = MakeUninitializedMetric(volume, xray, geometry);
  zero->SetNumberOfSamples(0);
  ExpectInitializeRefused(zero, "number of samples is 0");

  auto noShrink = MakeUninitializedMetric(volume, xray, geometry);
  noShrink->SetDetectorShrinkFactor(0);
  ExpectInitializeRefused(noShrink, "shrink factor is 0");

  auto negative = MakeUninitializedMetric(volume, xray, geometry);
  negative->SetSmoothingSigma(-2.0);
  ExpectInitializeRefused(negative, "smoothing sigma is -2");

  // A transform of another kind: not linear, so the points' motion has no affine Jacobian.
  auto bspline = MakeUninitializedMetric(volume, xray, geometry);
  bspline->SetMovingTransform(itk::BSplineTransform<double, 3, 3>::New());
  ExpectInitializeRefused(bspline, "not a linear transform");

  // A translation is linear: taken, its derivative the central difference.
  auto shift = MakeUninitializedMetric(volume, xray, geometry);
  auto translation = itk::TranslationTransform<double, 3>::New();
  shift->SetMovingTransform(translation);
  EXPECT_NO_THROW(shift->Initialize());
  EXPECT_EQ(shift->GetNumberOfParameters(), 3u);

  // The exact projector has no derivative.
  auto exact = MakeUninitializedMetric(volume, xray, geometry);
  exact->SetExactRaysPerPixelSide(2);
  exact->Initialize();
  EXPECT_TRUE(std::isfinite(exact->GetValue()));
  MetricType::DerivativeType derivative;
  EXPECT_THROW(exact->GetDerivative(derivative), itk::ExceptionObject);
}

TEST(PointBasedDRRMetricv4, APoseOutOfViewGivesZeroNotNaN)
{
  // The field is fixed at Initialize(); a pose that moves the CT out of every ray leaves a zero DRR there.
  const auto volume = MakePhantom();
  auto       pose = EulerPose(volume, { 0, 0, 0, 0, 0, 0 });
  auto       metric =
    MakeMetric(volume, ProjectionEnum::Perspective, { 90 }, pose, SimilarityEnum::GradientCorrelation, 100000);
  EulerType::ParametersType far = pose->GetParameters();
  far[3] = 5000.0;
  metric->SetParameters(far);
  MetricType::MeasureType    value;
  MetricType::DerivativeType derivative;
  metric->GetValueAndDerivative(value, derivative);
  EXPECT_EQ(value, 0.0);
  for (unsigned int j = 0; j < 6; ++j)
  {
    EXPECT_EQ(derivative[j], 0.0) << j;
  }
}

TEST(PointBasedDRRMetricv4, ITKv4OptimizersRecoverAKnownPose)
{
  // The metric, unchanged, in ITK's v4 optimizers that take its scales (QuasiNewton, which needs a scales estimator,
  // and the conjugate gradients with a line search, with the metric's), from 4 mm and 3 degrees away: each ends within
  // 0.3 mm (mTRE over the phantom's corners) of the pose the X-rays were rendered at.
  const auto volume = MakePhantom();
  for (const std::string name : { "quasinewton", "cg" })
  {
    auto pose = EulerPose(volume, { 0.04, -0.03, 0.05, 2.5, -2, 2 });
    auto metric =
      MakeMetric(volume, ProjectionEnum::Perspective, { 90, 0 }, pose, SimilarityEnum::GradientCorrelation, 500000);
    auto estimator = itk::PointBasedDRRParameterScalesEstimator<VolumeType>::New();
    estimator->SetMetric(metric);
    itk::GradientDescentOptimizerBasev4Template<double>::Pointer optimizer;
    if (name == "quasinewton")
    {
      optimizer = itk::QuasiNewtonOptimizerv4::New();
    }
    else
    {
      auto cg = itk::ConjugateGradientLineSearchOptimizerv4::New();
      cg->SetDoEstimateLearningRateOnce(true);
      cg->SetLowerLimit(0.0);
      cg->SetUpperLimit(5.0);
      cg->SetEpsilon(0.05);
      optimizer = cg;
    }
    optimizer->SetScalesEstimator(estimator);
    optimizer->SetNumberOfIterations(name == "cg" ? 40 : 100);
    optimizer->SetMetric(metric);
    optimizer->StartOptimization();
    double error = 0.0;
    for (unsigned int corner = 0; corner < 8; ++corner)
    {
      itk::ContinuousIndex<double, 3> index;
      for (unsigned int a = 0; a < 3; ++a)
      {
        index[a] = (corner >> a) & 1u ? volume->GetLargestPossibleRegion().GetSize()[a] - 1.0 : 0.0;
      }
      VolumeType::PointType corner3;
      volume->TransformContinuousIndexToPhysicalPoint(index, corner3);
      error += (pose->TransformPoint(corner3) - corner3).GetNorm() / 8.0;
    }
    EXPECT_LT(error, 0.3) << name << ": " << optimizer->GetStopConditionDescription();
    EXPECT_GT(metric->GetNumberOfDerivativeEvaluations(), 0u) << name;
  }
}
