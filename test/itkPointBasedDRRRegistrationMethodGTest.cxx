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
// PointBasedDRRRegistrationMethod: the pose it finds on X-rays rendered at a known pose of an asymmetric phantom, the
// events it sends, and the input it refuses; DRRImageSimilarity's metrics.
#include "itkPointBasedDRRRegistrationMethod.h"
#include "itkDRRImageSimilarity.h"
#include "itkExactDRRImageFilter.h"
#include "PointBasedDRRTestHelpers.h"
#include "gtest/gtest.h"

#include <cmath>
#include <string>
#include <vector>

namespace
{
using VolumeType = itk::Image<float, 3>;
using MethodType = itk::PointBasedDRRRegistrationMethod<VolumeType>;
using XRayType = MethodType::XRayImageType;
using GeometryType = itk::DRRProjectionGeometry;

/** The registration tests' CT (PointBasedDRRTestHelpers.h). */
VolumeType::Pointer
MakePhantom()
{
  return PointBasedDRRTest::MakeAsymmetricPhantom();
}

/** A cone-beam view, 48 x 40 pixels of 4 mm at the detector (the phantom's shadow and air around it), about the room
 * origin (the phantom's centre). */
GeometryType::Pointer
View(double gantryInDegrees)
{
  auto geometry = GeometryType::New();
  geometry->SetGantryAngleInDegrees(gantryInDegrees);
  geometry->SetDetectorSize({ { 48, 40 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(4.0));
  return geometry;
}

/** The "X-ray": the exact DRR (2 x 2 rays per pixel, the method's own exact model) of the phantom at the pose. */
XRayType::Pointer
RenderXRay(const VolumeType * volume, const GeometryType * geometry, const MethodType::PoseType & pose)
{
  auto filter = itk::ExactDRRImageFilter<VolumeType, XRayType>::New();
  filter->SetInput(volume);
  filter->SetGeometry(const_cast<GeometryType *>(geometry));
  filter->SetTransform(MethodType::MakePoseTransform(volume, pose)->GetInverseTransform());
  filter->SetRaysPerPixelSide(2);
  filter->Update();
  XRayType::Pointer image = filter->GetOutput();
  image->DisconnectPipeline();
  return image;
}

/** A method set up with the phantom and an AP and a lateral X-ray at truth. */
MethodType::Pointer
MakeMethod(const VolumeType * volume, const MethodType::PoseType & truth)
{
  auto method = MethodType::New();
  method->SetVolume(volume);
  for (const double gantry : { 90.0, 0.0 })
  {
    const auto geometry = View(gantry);
    method->AddXRay(RenderXRay(volume, geometry, truth), geometry);
  }
  method->GetModifiableMetric()->SetExactRaysPerPixelSide(2);
  method->SetShrinkFactorsPerLevel({ 2, 1 });
  method->SetNumberOfSamplesPerLevel({});
  method->SetSmoothingSigmasPerLevel({});
  return method;
}

/** Update() throws an itk::ExceptionObject whose description contains what. */
void
ExpectRefused(MethodType * method, const std::string & what)
{
  try
  {
    method->Update();
    ADD_FAILURE() << "no exception; expected one about '" << what << "'";
  }
  catch (const itk::ExceptionObject & error)
  {
    EXPECT_NE(std::string(error.GetDescription()).find(what), std::string::npos) << error.GetDescription();
  }
}
} // namespace

TEST(DRRImageSimilarity, NormalizedCorrelationIsBlindToGainAndOffsetAndSeesSign)
{
  const std::vector<float>   a{ 1, 4, 2, 8, 5, 7, 100 };
  std::vector<float>         b(a.size()), c(a.size());
  const std::vector<uint8_t> mask{ 1, 1, 1, 1, 1, 1, 0 }; // the last pixel is outside the field
  for (size_t p = 0; p < a.size(); ++p)
  {
    b[p] = 3.0f * a[p] + 2.0f;
    c[p] = -a[p];
  }
  b.back() = -1000.0f;
  EXPECT_NEAR(itk::DRRImageSimilarity::MaskedNormalizedCorrelation(a.data(), b.data(), mask), 1.0, 1e-12);
  EXPECT_NEAR(itk::DRRImageSimilarity::MaskedNormalizedCorrelation(a.data(), c.data(), mask), -1.0, 1e-12);
  const std::vector<float> flat(a.size(), 5.0f);
  EXPECT_EQ(itk::DRRImageSimilarity::MaskedNormalizedCorrelation(a.data(), flat.data(), mask), 0.0);
  EXPECT_EQ(itk::DRRImageSimilarity::MaskedNormalizedCorrelation(a.data(), b.data(), std::vector<uint8_t>(a.size(), 0)),
            0.0);
}

// Gradient correlation: 1 for a gain and an offset of the same image, blind to a smooth ramp added (its differences
// are constant), and the names list is what Evaluate() takes.
TEST(DRRImageSimilarity, GradientCorrelationSeesEdgesOnly)
{
  const size_t         columns = 6, rows = 5;
  std::vector<float>   a(columns * rows), b(a.size()), ramp(a.size());
  std::vector<uint8_t> mask(a.size(), 1);
  for (size_t p = 0; p < a.size(); ++p)
  {
    a[p] = static_cast<float>((p * 7919) % 13);
    b[p] = 2.0f * a[p] + 5.0f;
    ramp[p] = a[p] + 0.5f * static_cast<float>(p % columns) + 0.25f * static_cast<float>(p / columns);
  }
  EXPECT_NEAR(itk::DRRImageSimilarity::MaskedGradientCorrelation(a.data(), b.data(), mask, columns), 1.0, 1e-12);
  EXPECT_LT(itk::DRRImageSimilarity::MaskedNormalizedCorrelation(a.data(), ramp.data(), mask), 0.99);
  EXPECT_GT(itk::DRRImageSimilarity::MaskedGradientCorrelation(a.data(), ramp.data(), mask, columns),
            itk::DRRImageSimilarity::MaskedNormalizedCorrelation(a.data(), ramp.data(), mask));
  ASSERT_EQ(itk::DRRImageSimilarity::GetMetricNames(), (std::vector<std::string>{ "ncc", "gc" }));
  EXPECT_EQ(itk::DRRImageSimilarity::JoinMetricNames(" or "), "ncc or gc");
  for (const std::string & name : itk::DRRImageSimilarity::GetMetricNames())
  {
    EXPECT_NEAR(itk::DRRImageSimilarity::Evaluate(name, a.data(), b.data(), mask, columns), 1.0, 1e-12) << name;
  }
  EXPECT_THROW(itk::DRRImageSimilarity::Evaluate("mi", a.data(), b.data(), mask, columns), itk::ExceptionObject);
  EXPECT_FALSE(itk::DRRImageSimilarity::IsMetricName("mi"));
  (void)rows;
}

// From the identity, the pose the X-rays were rendered at. The DRRs are rendered by the very model that made the
// X-rays (exact projector, box kernel, 2 x 2 rays per pixel), so the similarity is 1 at the truth and nowhere else
// near it: what is left of the error is the search's. The exact projector has no derivative, so the method runs
// Powell's method (PowellOptimizerv4), which stops on the last level (shrink 1) when a line search brackets its minimum
// within the step tolerance, 0.02 mm of the points' motion (the parameters as the method presents them: a rotation's
// unit is its RMS lever arm, about 20 mm here, so 0.02 mm is 0.06 degrees): 0.1 mm and 0.15 degrees allow for the six
// directions' line searches to end each within it, and are ten times below what a wrong geometry or transform
// direction gives (the truth's 1.5 to 3 mm and degrees).
TEST(PointBasedDRRRegistrationMethod, FindsThePoseTheXRaysWereRenderedAt)
{
  const auto                 volume = MakePhantom();
  const MethodType::PoseType truth{ std::array<double, 6>{ { 2.0, -1.5, 1.0, 1.5, -1.0, 2.0 } }.data() };
  auto                       method = MakeMethod(volume, truth);
  std::vector<unsigned int>  levels;
  std::vector<double>        progress;
  method->AddObserver(itk::IterationEvent(), [&](const itk::EventObject &) {
    levels.push_back(method->GetCurrentShrinkFactor());
    EXPECT_GT(method->GetCurrentLevelEvaluations(), 0u);
  });
  method->AddObserver(itk::ProgressEvent(),
                      [&](const itk::EventObject &) { progress.push_back(method->GetProgress()); });
  method->Update();

  const MethodType::PoseType pose = method->GetPose();
  for (unsigned int k = 0; k < 6; ++k)
  {
    EXPECT_NEAR(pose[k], truth[k], k < 3 ? 0.1 : 0.15) << "pose component " << k << (k < 3 ? " (mm)" : " (degrees)");
  }
  EXPECT_GT(method->GetSimilarity(), 0.999);
  EXPECT_EQ(method->GetNumberOfDerivativeEvaluations(), 0u);
  EXPECT_LT(method->GetStartSimilarity(), method->GetSimilarity());
  EXPECT_FALSE(method->GetStoppedByTimeLimit());
  EXPECT_GT(method->GetNumberOfEvaluations(), 0u);
  EXPECT_EQ(levels, (std::vector<unsigned int>{ 2, 1 }));
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), 1.0);

  // The output transform is the pose's (the pose in degrees back to radians: equal to rounding).
  const auto expected = MethodType::MakePoseTransform(volume, pose);
  for (unsigned int k = 0; k < 6; ++k)
  {
    EXPECT_NEAR(method->GetTransform()->GetParameters()[k], expected->GetParameters()[k], 1e-12); // degrees round trip
  }
  EXPECT_EQ(method->GetTransform()->GetCenter(), expected->GetCenter());
  EXPECT_EQ(method->GetTransformOutput()->Get(), method->GetTransform());

  // The final DRRs and masks: full resolution, the field covered.
  for (unsigned int x = 0; x < 2; ++x)
  {
    ASSERT_NE(method->GetFinalDRR(x), nullptr);
    ASSERT_NE(method->GetFinalMask(x), nullptr);
    EXPECT_EQ(method->GetFinalDRR(x)->GetLargestPossibleRegion().GetSize(),
              method->GetXRayImage(x)->GetLargestPossibleRegion().GetSize());
    EXPECT_EQ(method->GetFinalMask(x)->GetLargestPossibleRegion().GetSize(),
              method->GetXRayImage(x)->GetLargestPossibleRegion().GetSize());
    size_t covered = 0;
    for (size_t p = 0; p < 48 * 40; ++p)
    {
      covered += method->GetFinalMask(x)->GetBufferPointer()[p];
    }
    EXPECT_GT(covered, 100u);
    EXPECT_LT(covered, 48u * 40u);
  }
  EXPECT_EQ(method->GetFinalDRR(2), nullptr);

  // Up to date: a second Update() does not register again.
  const auto evaluations = method->GetNumberOfEvaluations();
  levels.clear();
  method->Update();
  EXPECT_TRUE(levels.empty());
  EXPECT_EQ(method->GetNumberOfEvaluations(), evaluations);
}

// Kept points: the same seed gives the same pose, bit for bit, on another number of threads.
TEST(PointBasedDRRRegistrationMethod, KeptPointsGiveTheSamePoseOnAnyNumberOfThreads)
{
  const auto                 volume = MakePhantom();
  const MethodType::PoseType truth{ std::array<double, 6>{ { 1.0, 1.0, -1.0, 1.0, 1.0, -1.0 } }.data() };
  MethodType::PoseType       poses[2];
  for (unsigned int run = 0; run < 2; ++run)
  {
    auto method = MakeMethod(volume, truth);
    method->GetModifiableMetric()->SetExactRaysPerPixelSide(0);
    method->GetModifiableMetric()->SetNumberOfSamples(200000);
    method->GetModifiableMetric()->SetSeed(7);
    method->SetShrinkFactorsPerLevel({ 2 });
    method->SetNumberOfWorkUnits(run == 0 ? 1 : 3);
    method->Update();
    poses[run] = method->GetPose();
    EXPECT_GT(method->GetSimilarity(), 0.9);
    EXPECT_GT(method->GetNumberOfDerivativeEvaluations(), 0u);
  }
  EXPECT_EQ(poses[0], poses[1]);
}

TEST(PointBasedDRRRegistrationMethod, RefusesInputItCannotUse)
{
  const auto                 volume = MakePhantom();
  const MethodType::PoseType identity(0.0);

  auto noVolume = MethodType::New();
  noVolume->AddXRay(RenderXRay(volume, View(90.0), identity), View(90.0));
  EXPECT_THROW(noVolume->Update(), itk::ExceptionObject);

  auto noXRay = MethodType::New();
  noXRay->SetVolume(volume);
  ExpectRefused(noXRay, "at least one X-ray");

  auto empty = VolumeType::New();
  empty->SetRegions(VolumeType::SizeType{ { 0, 28, 24 } });
  empty->Allocate();
  auto emptyVolume = MakeMethod(volume, identity);
  emptyVolume->SetVolume(empty);
  ExpectRefused(emptyVolume, "volume is empty");

  auto zeroSamples = MakeMethod(volume, identity);
  zeroSamples->GetModifiableMetric()->SetExactRaysPerPixelSide(0);
  zeroSamples->GetModifiableMetric()->SetNumberOfSamples(0);
  ExpectRefused(zeroSamples, "number of samples is 0");

  auto zeroSamplesOnALevel = MakeMethod(volume, identity);
  zeroSamplesOnALevel->GetModifiableMetric()->SetExactRaysPerPixelSide(0);
  zeroSamplesOnALevel->SetNumberOfSamplesPerLevel({ 100000, 0 });
  ExpectRefused(zeroSamplesOnALevel, "number of samples is 0");

  auto samplesPerLevel = MakeMethod(volume, identity);
  samplesPerLevel->SetNumberOfSamplesPerLevel({ 100000 });
  ExpectRefused(samplesPerLevel, "the schedule has 2 levels but 1 numbers of samples");

  auto sigmasPerLevel = MakeMethod(volume, identity);
  sigmasPerLevel->SetSmoothingSigmasPerLevel({ 1.0, 2.0, 3.0 });
  ExpectRefused(sigmasPerLevel, "the schedule has 2 levels but 3 smoothing sigmas");

  auto negativeSigma = MakeMethod(volume, identity);
  negativeSigma->SetSmoothingSigmasPerLevel({ -1.0, 0.0 });
  ExpectRefused(negativeSigma, "smoothing sigma is -1");

  auto zeroShrink = MakeMethod(volume, identity);
  zeroShrink->SetShrinkFactorsPerLevel({ 2, 0 });
  ExpectRefused(zeroShrink, "shrink factor is 0");

  auto noLevel = MakeMethod(volume, identity);
  noLevel->SetShrinkFactorsPerLevel({});
  ExpectRefused(noLevel, "no level");

  EXPECT_THROW(MethodType::MakeOptimizer("newton"), itk::ExceptionObject);

  auto negativeTime = MakeMethod(volume, identity);
  negativeTime->SetMaximumTimeInSeconds(-1.0);
  ExpectRefused(negativeTime, "time limit");

  auto wrongSize = MethodType::New();
  wrongSize->SetVolume(volume);
  auto otherView = View(90.0);
  otherView->SetDetectorSize({ { 40, 40 } });
  wrongSize->AddXRay(RenderXRay(volume, View(90.0), identity), otherView);
  ExpectRefused(wrongSize, "48 x 40 pixels, its view 40 x 40");

  auto noGeometry = MethodType::New();
  noGeometry->SetVolume(volume);
  noGeometry->AddXRay(RenderXRay(volume, View(90.0), identity), nullptr);
  ExpectRefused(noGeometry, "no image or no geometry");
}
