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
// The polychromatic image (issue 16, item 2): DRRPolychromaticImageFilter against the closed form of water slabs
// (beam hardening), two materials, the Jensen bias correction and the delta-method standard error on Gaussian noise
// of known covariance, and its bad inputs.
#include "itkDRRPolychromaticImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkImage.h"
#include "itkVectorImage.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <xraylib.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <random>
#include <vector>

namespace
{
using PointBasedDRRTest::UpdateError;
using ChannelImageType = itk::VectorImage<float, 2>;
using OutputImageType = itk::Image<double, 2>;
using FloatImageType = itk::Image<float, 2>;
using FilterType = itk::DRRPolychromaticImageFilter<ChannelImageType, OutputImageType>;

ChannelImageType::Pointer
MakeChannels(unsigned int width, unsigned int height, unsigned int components)
{
  auto image = ChannelImageType::New();
  image->SetRegions(ChannelImageType::SizeType{ { width, height } });
  image->SetNumberOfComponentsPerPixel(components);
  image->Allocate();
  return image;
}

itk::DRRMaterialTable::Pointer
Table(const std::vector<const char *> & materials)
{
  auto         table = itk::DRRMaterialTable::New();
  const double inf = std::numeric_limits<double>::infinity();
  for (size_t m = 0; m < materials.size(); ++m)
  {
    table->AddMaterial(
      m == 0 ? -inf : 100.0 * m, m + 1 == materials.size() ? inf : 100.0 * (m + 1), materials[m], 1.0, 1.0);
  }
  return table;
}

// Effective energy of a transmission through t mm of water: (mu/rho)_w(E) t / 10 = -ln T, by bisection (mu/rho of
// water decreases with E from 10 to 200 keV).
double
EffectiveEnergy(double minusLogT, double thickness)
{
  double low = 10.0, high = 200.0;
  for (int i = 0; i < 100; ++i)
  {
    const double middle = 0.5 * (low + high);
    (CS_Total_CP("Water, Liquid", middle, nullptr) * thickness / 10.0 > minusLogT ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

} // namespace

TEST(DRRPolychromaticImageFilter, WaterSlabsMatchTheClosedFormAndHarden)
{
  const double       reference = 60.0;
  const char *       water = "Water, Liquid";
  const double       muReference = CS_Total_CP(water, reference, nullptr) / 10.0; // 1/mm at 1 g/cm^3
  const double       thicknesses[] = { 1.0, 10.0, 100.0, 300.0 };
  auto               channels = MakeChannels(4, 1, 1);
  std::vector<float> L(4);
  for (unsigned int i = 0; i < 4; ++i)
  {
    L[i] = static_cast<float>(muReference * thicknesses[i]);
    ChannelImageType::PixelType pixel(1);
    pixel[0] = L[i];
    channels->SetPixel({ { i, 0 } }, pixel);
  }
  for (const double kVp : { 70.0, 120.0 })
  {
    auto spectrum = itk::DRRXRaySpectrum::New();
    spectrum->SetKramers(kVp, 2.5, 1.0);
    auto filter = FilterType::New();
    filter->SetInput(channels);
    filter->SetMaterialTable(Table({ water }));
    filter->SetSpectrum(spectrum);
    filter->SetReferenceEnergyInKeV(reference);
    filter->SetOutputTransmission(true);
    filter->Update();
    auto logFilter = FilterType::New();
    logFilter->SetInput(channels);
    logFilter->SetMaterialTable(Table({ water }));
    logFilter->SetSpectrum(spectrum);
    logFilter->Update();
    double previous = 0.0;
    for (unsigned int i = 0; i < 4; ++i)
    {
      // The slab the float channel holds: t = L / mu_ref.
      const double t = static_cast<double>(L[i]) / muReference;
      double       sum = 0.0, transmitted = 0.0;
      for (size_t e = 0; e < spectrum->GetNumberOfBins(); ++e)
      {
        const double s = spectrum->GetFluence()[e];
        sum += s;
        transmitted += s * std::exp(-1.0 * CS_Total_CP(water, spectrum->GetEnergies()[e], nullptr) * t / 10.0);
      }
      const double expected = transmitted / sum;
      const double T = filter->GetOutput()->GetPixel({ { i, 0 } });
      EXPECT_NEAR(T / expected, 1.0, 1e-6) << kVp << " kVp, " << thicknesses[i] << " mm";
      EXPECT_NEAR(logFilter->GetOutput()->GetPixel({ { i, 0 } }), -std::log(expected), 1e-6 * -std::log(expected));
      EXPECT_EQ(filter->GetStandardErrorOutput()->GetPixel({ { i, 0 } }), 0.0); // no covariance
      const double energy = EffectiveEnergy(-std::log(T), t);
      std::cout << kVp << " kVp, 2.5 mm Al: water " << thicknesses[i] << " mm: T " << T << ", -ln T " << -std::log(T)
                << ", E_eff " << energy << " keV" << std::endl;
      EXPECT_GT(energy, previous) << "beam hardening: E_eff must increase with the thickness";
      previous = energy;
    }
  }
}

TEST(DRRPolychromaticImageFilter, TwoMaterialsMatchTheClosedForm)
{
  const char *                soft = "Tissue, Soft (ICRP)";
  const char *                bone = "Bone, Cortical (ICRP)";
  const double                reference = 70.0;
  auto                        channels = MakeChannels(1, 1, 2);
  ChannelImageType::PixelType pixel(2);
  pixel[0] = 3.0f;
  pixel[1] = 1.25f;
  channels->SetPixel({ { 0, 0 } }, pixel);
  auto spectrum = itk::DRRXRaySpectrum::New();
  spectrum->SetSpectrum({ 40.0, 60.0, 90.0 }, { 1.0, 2.0, 0.5 });
  auto filter = FilterType::New();
  filter->SetInput(channels);
  filter->SetMaterialTable(Table({ soft, bone }));
  filter->SetSpectrum(spectrum);
  filter->SetReferenceEnergyInKeV(reference);
  filter->Update();
  double T = 0.0;
  for (size_t e = 0; e < 3; ++e)
  {
    const double energy = spectrum->GetEnergies()[e];
    const double x = 3.0 * CS_Total_CP(soft, energy, nullptr) / CS_Total_CP(soft, reference, nullptr) +
                     1.25 * CS_Total_CP(bone, energy, nullptr) / CS_Total_CP(bone, reference, nullptr);
    T += spectrum->GetFluence()[e] * std::exp(-x) / 3.5;
  }
  EXPECT_NEAR(filter->GetOutput()->GetPixel({ { 0, 0 } }), -std::log(T), 1e-12);
  ASSERT_EQ(filter->GetAttenuationRatios().size(), 6u);
  EXPECT_DOUBLE_EQ(filter->GetAttenuationRatios()[4],
                   CS_Total_CP(bone, 60.0, nullptr) / CS_Total_CP(bone, 70.0, nullptr));
}

namespace
{
struct NoiseResult
{
  double TrueT{ 0.0 };
  double PredictedBias{ 0.0 }; // E[T_hat] - T for Gaussian L_hat: sum w exp(-k.L) (exp(k^T C k / 2) - 1)
  double Mean[2]{ 0.0, 0.0 };  // mean T over pixels: uncorrected, corrected
  double StandardErrorOfMean[2]{ 0.0, 0.0 };
  double SampleVariance{ 0.0 };      // of the uncorrected T over pixels
  double MeanSquaredOutputSE{ 0.0 }; // of the uncorrected filter's standard-error output (T)
};

// N pixels of L_hat ~ N(L, C) (fixed seed) through the filter, uncorrected and corrected, output T.
NoiseResult
RunNoise(double scale, unsigned int side)
{
  const char *                     soft = "Tissue, Soft (ICRP)";
  const char *                     bone = "Bone, Cortical (ICRP)";
  const double                     L[2] = { 4.0, 1.5 };
  const double                     C[3] = { 0.02 * scale, 0.006 * scale, 0.01 * scale }; // (0,0), (0,1), (1,1)
  const double                     a = std::sqrt(C[0]), b = C[1] / a, c = std::sqrt(C[2] - b * b); // Cholesky
  auto                             channels = MakeChannels(side, side, 2);
  auto                             covariance = MakeChannels(side, side, 3);
  std::mt19937_64                  generator(20240916);
  std::normal_distribution<double> normal;
  ChannelImageType::PixelType      pixel(2), cov(3);
  for (unsigned int k = 0; k < 3; ++k)
  {
    cov[k] = static_cast<float>(C[k]);
  }
  for (unsigned int y = 0; y < side; ++y)
  {
    for (unsigned int x = 0; x < side; ++x)
    {
      const double z0 = normal(generator), z1 = normal(generator);
      pixel[0] = static_cast<float>(L[0] + a * z0);
      pixel[1] = static_cast<float>(L[1] + b * z0 + c * z1);
      channels->SetPixel({ { x, y } }, pixel);
      covariance->SetPixel({ { x, y } }, cov);
    }
  }
  // Kramers at 120 kVp with 2.5 mm Al from 30 keV: below, k_m(E) is so large that the Gaussian closed form's
  // exp(k^T C k / 2) is dominated by bins of negligible fluence that no sample of this size explores.
  auto kramers = itk::DRRXRaySpectrum::New();
  kramers->SetKramers(120.0, 2.5, 2.0);
  std::vector<double> energies, fluence;
  for (size_t e = 0; e < kramers->GetNumberOfBins(); ++e)
  {
    if (kramers->GetEnergies()[e] >= 30.0)
    {
      energies.push_back(kramers->GetEnergies()[e]);
      fluence.push_back(kramers->GetFluence()[e]);
    }
  }
  auto spectrum = itk::DRRXRaySpectrum::New();
  spectrum->SetSpectrum(energies, fluence);
  auto        table = Table({ soft, bone });
  NoiseResult result;
  for (int corrected = 0; corrected < 2; ++corrected)
  {
    auto filter = FilterType::New();
    filter->SetInput(channels);
    filter->SetCovarianceInput(covariance);
    filter->SetMaterialTable(table);
    filter->SetSpectrum(spectrum);
    filter->SetOutputTransmission(true);
    filter->SetCorrectJensenBias(corrected == 1);
    filter->Update();
    const double * out = filter->GetOutput()->GetBufferPointer();
    const double * se = filter->GetStandardErrorOutput()->GetBufferPointer();
    const size_t   n = static_cast<size_t>(side) * side;
    double         sum = 0.0, sumOfSquares = 0.0, se2 = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
      sum += out[i];
      sumOfSquares += out[i] * out[i];
      se2 += se[i] * se[i];
    }
    const double mean = sum / n;
    const double variance = (sumOfSquares - n * mean * mean) / (n - 1.0);
    result.Mean[corrected] = mean;
    result.StandardErrorOfMean[corrected] = std::sqrt(variance / n);
    if (corrected == 0)
    {
      result.SampleVariance = variance;
      result.MeanSquaredOutputSE = se2 / n;
    }
    if (corrected == 1)
    {
      // The closed forms, with the filter's own k_m(E) (checked against xraylib in TwoMaterialsMatchTheClosedForm).
      const auto &        k = filter->GetAttenuationRatios();
      const size_t        nE = k.size() / 2;
      std::vector<double> weights; // the filter's bins: those of nonzero fluence
      double              total = 0.0;
      for (const double s : spectrum->GetFluence())
      {
        if (s > 0.0)
        {
          weights.push_back(s);
          total += s;
        }
      }
      EXPECT_EQ(weights.size(), nE);
      for (size_t e = 0; e < nE; ++e)
      {
        const double w = weights[e] / total;
        const double k0 = k[e], k1 = k[nE + e];
        const double q = k0 * k0 * C[0] + 2.0 * k0 * k1 * C[1] + k1 * k1 * C[2];
        const double t = w * std::exp(-(k0 * L[0] + k1 * L[1]));
        result.TrueT += t;
        result.PredictedBias += w * std::exp(-(k0 * L[0] + k1 * L[1]) + 0.5 * q) - t; // no inf x 0
      }
    }
  }
  return result;
}
} // namespace

TEST(DRRPolychromaticImageFilter, JensenCorrectionRemovesTheBiasOfGaussianEstimates)
{
  const NoiseResult r = RunNoise(1.0, 200);
  const double      biasUncorrected = r.Mean[0] - r.TrueT;
  const double      biasCorrected = r.Mean[1] - r.TrueT;
  std::cout << "T " << r.TrueT << ", predicted bias " << r.PredictedBias << " (" << r.PredictedBias / r.TrueT * 100.0
            << " %); uncorrected mean " << r.Mean[0] << " (bias " << biasUncorrected / r.StandardErrorOfMean[0]
            << " SEM), corrected mean " << r.Mean[1] << " (bias " << biasCorrected / r.StandardErrorOfMean[1] << " SEM)"
            << std::endl;
  // The uncorrected mean is biased, by the predicted amount; the corrected one is not.
  EXPECT_GT(std::abs(biasUncorrected) / r.StandardErrorOfMean[0], 8.0);
  EXPECT_LT(std::abs(biasUncorrected - r.PredictedBias) / r.StandardErrorOfMean[0], 4.0);
  EXPECT_LT(std::abs(biasCorrected) / r.StandardErrorOfMean[1], 4.0);
}

TEST(DRRPolychromaticImageFilter, StandardErrorMatchesTheSpreadAcrossPixels)
{
  // Small noise (k^T C k ~ 0.003), where the delta method holds to ~0.5 %: (n-1) s^2 / sigma^2 is chi-square with
  // n-1 degrees of freedom, s^2 / sigma^2 - 1 has the standard deviation sqrt(2 / (n - 1)).
  const unsigned int side = 200;
  const NoiseResult  r = RunNoise(0.05, side);
  const double       n = static_cast<double>(side) * side;
  const double       z = (r.SampleVariance / r.MeanSquaredOutputSE - 1.0) / std::sqrt(2.0 / (n - 1.0));
  std::cout << "sample variance of T " << r.SampleVariance << ", mean SE^2 " << r.MeanSquaredOutputSE << ", z " << z
            << std::endl;
  EXPECT_LT(std::abs(z), 5.0);
}

TEST(DRRPolychromaticImageFilter, BadInputsThrow)
{
  auto spectrum = itk::DRRXRaySpectrum::New();
  spectrum->SetKramers(100.0);
  auto                        channels = MakeChannels(3, 2, 2);
  ChannelImageType::PixelType zero(2);
  zero.Fill(0.0f);
  channels->FillBuffer(zero);
  auto filter = FilterType::New();
  filter->SetInput(channels);
  EXPECT_NE(UpdateError(filter).find("no material table"), std::string::npos);
  filter->SetMaterialTable(Table({ "H2O" }));
  EXPECT_NE(UpdateError(filter).find("no X-ray spectrum"), std::string::npos);
  filter->SetSpectrum(spectrum);
  EXPECT_NE(UpdateError(filter).find("the channel image has 2 channels, the material table 1 materials"),
            std::string::npos);
  filter->SetMaterialTable(Table({ "H2O", "Ca" }));
  EXPECT_EQ(UpdateError(filter), "");
  ChannelImageType::PixelType bad(2);
  bad[0] = 1.0f;
  bad[1] = std::numeric_limits<float>::quiet_NaN();
  channels->SetPixel({ { 2, 1 } }, bad);
  channels->Modified();
  EXPECT_NE(UpdateError(filter).find("channel 1 of pixel [2, 1] is nan"), std::string::npos) << UpdateError(filter);
  channels->SetPixel({ { 2, 1 } }, zero);
  channels->Modified();
  auto covariance = MakeChannels(3, 2, 2);
  filter->SetCovarianceInput(covariance);
  EXPECT_NE(UpdateError(filter).find("the covariance image has 2 components; 2 channels need K(K+1)/2 = 3"),
            std::string::npos);
  covariance = MakeChannels(3, 2, 3);
  ChannelImageType::PixelType c(3);
  c.Fill(0.0f);
  covariance->FillBuffer(c);
  c[2] = -0.1f;
  covariance->SetPixel({ { 1, 0 } }, c);
  filter->SetCovarianceInput(covariance);
  EXPECT_NE(UpdateError(filter).find("covariance (1, 1) of pixel [1, 0] is -0.1"), std::string::npos)
    << UpdateError(filter);
  filter->SetCovarianceInput(MakeChannels(4, 3, 3)); // (a smaller one fails ITK's requested-region check first)
  const std::string regionError = UpdateError(filter);
  EXPECT_NE(regionError.find("is not the channel image's"), std::string::npos) << regionError;
  filter->SetCovarianceInput(nullptr);
  EXPECT_EQ(UpdateError(filter), "");
  filter->SetReferenceEnergyInKeV(0.0);
  const std::string energyError = UpdateError(filter);
  EXPECT_NE(energyError.find("the reference energy must be in"), std::string::npos) << energyError;
  std::ostringstream print;
  filter->Print(print);
  EXPECT_NE(print.str().find("CorrectJensenBias"), std::string::npos);
}

TEST(DRRPolychromaticImageFilter, FloatOutputAndHugeLineIntegralsStayFinite)
{
  using FloatFilterType = itk::DRRPolychromaticImageFilter<ChannelImageType, FloatImageType>;
  auto                        channels = MakeChannels(1, 1, 1);
  ChannelImageType::PixelType pixel(1);
  pixel[0] = 5000.0f; // T underflows: -ln T stays finite
  channels->SetPixel({ { 0, 0 } }, pixel);
  auto spectrum = itk::DRRXRaySpectrum::New();
  spectrum->SetKramers(120.0);
  auto filter = FloatFilterType::New();
  filter->SetInput(channels);
  filter->SetMaterialTable(Table({ "Water, Liquid" }));
  filter->SetSpectrum(spectrum);
  filter->Update();
  const float value = filter->GetOutput()->GetPixel({ { 0, 0 } });
  EXPECT_TRUE(std::isfinite(value));
  EXPECT_GT(value, 1000.0f);
}

// End to end (docs/design.md section 14): a CT of water (0 HU) rendered by the exact projector with material channels
// (the Materials transfer function at E_ref), then through the polychromatic filter: the central ray crosses 30 mm of
// water, whose transmission is the closed form sum_E S(E) exp(-(mu/rho)_w(E) rho t) / sum_E S(E), to 1e-6, at 70 and
// 120 kVp. The point-based filter's material channels, averaged over seeds, give the same -ln T within their spread.
TEST(DRRPolychromaticPipeline, AWaterSlabThroughTheProjectorsMatchesTheClosedForm)
{
  using CTType = itk::Image<short, 3>;
  auto ct = CTType::New();
  ct->SetRegions(CTType::SizeType{ { 30, 30, 30 } });
  ct->Allocate();
  ct->FillBuffer(0);
  CTType::PointType centre;
  centre.Fill(14.5); // spacing 1 mm, origin 0: the volume spans [-0.5, 29.5] mm per axis
  const double inf = std::numeric_limits<double>::infinity();
  auto         table = itk::DRRMaterialTable::New();
  table->AddMaterial(-inf, -500.0, "Air, Dry (near sea level)", 0.0, 0.0);
  table->AddMaterial(-500.0, inf, "Water, Liquid", 1.0, 1.0);
  const double reference = 60.0;
  auto         geometry = itk::DRRProjectionGeometry::New();
  geometry->SetProjection(itk::DRRProjectionGeometry::ProjectionEnum::Parallel);
  geometry->SetIsocenter(centre);
  geometry->SetDetectorSize({ { 3, 3 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(0.5));
  const auto render = [&](auto drr) {
    drr->SetInput(ct);
    drr->SetGeometry(geometry);
    drr->GetTransferFunction()->SetEffectiveEnergyInKeV(reference);
    drr->GetTransferFunction()->SetMaterialTable(table);
    drr->SetMaterialChannels(true);
    drr->Update();
    return drr;
  };
  const auto exact = render(itk::ExactDRRImageFilter<CTType, FloatImageType>::New());
  ASSERT_EQ(exact->GetChannelOutput()->GetNumberOfComponentsPerPixel(), 2u);
  const auto points = itk::PointBasedDRRImageFilter<CTType, FloatImageType>::New();
  points->SetNumberOfSamples(200000);
  render(points);
  for (const double kVp : { 70.0, 120.0 })
  {
    auto spectrum = itk::DRRXRaySpectrum::New();
    spectrum->SetKramers(kVp);
    double sum = 0.0, transmitted = 0.0;
    for (size_t e = 0; e < spectrum->GetNumberOfBins(); ++e)
    {
      sum += spectrum->GetFluence()[e];
      transmitted +=
        spectrum->GetFluence()[e] * std::exp(-CS_Total_CP("Water, Liquid", spectrum->GetEnergies()[e], nullptr) * 3.0);
    }
    const double expected = -std::log(transmitted / sum);
    const auto   polychromatic = [&](auto * drr) {
      auto filter = itk::DRRPolychromaticImageFilter<ChannelImageType, OutputImageType>::New();
      filter->SetInput(drr->GetChannelOutput());
      filter->SetCovarianceInput(drr->GetChannelCovarianceOutput());
      filter->SetMaterialTable(table);
      filter->SetSpectrum(spectrum);
      filter->SetReferenceEnergyInKeV(reference);
      filter->Update();
      return std::make_pair(filter->GetOutput()->GetPixel({ { 1, 1 } }),
                            filter->GetStandardErrorOutput()->GetPixel({ { 1, 1 } }));
    };
    EXPECT_NEAR(polychromatic(exact.GetPointer()).first, expected, 1e-6 * expected) << kVp << " kVp";
    double             mean = 0.0, predictedVariance = 0.0;
    const unsigned int seeds = 32;
    for (unsigned int seed = 0; seed < seeds; ++seed)
    {
      points->SetSeed(seed);
      points->Update();
      const auto value = polychromatic(points.GetPointer());
      mean += value.first / seeds;
      predictedVariance += value.second * value.second / seeds;
    }
    EXPECT_NEAR(mean, expected, 5.0 * std::sqrt(predictedVariance / seeds)) << kVp << " kVp, points";
  }
}
