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
// Quantum noise (issue 16, item 3): Poisson counts against their closed forms (mean, variance, the probability of no
// photon, the probability mass around the mean), the filter's counts per pixel, and reproducibility.
#include "itkDRRPoissonSampler.h"
#include "itkDRRQuantumNoiseImageFilter.h"
#include "itkImage.h"

#include "gtest/gtest.h"

#include <cmath>
#include <cstring>
#include <vector>

namespace
{
using ImageType = itk::Image<float, 2>;

struct Moments
{
  double Mean{ 0.0 };
  double Variance{ 0.0 };
  double Zeros{ 0.0 }; // fraction of zero counts
};

Moments
DrawCounts(double mean, uint64_t chunk, size_t n, std::vector<uint64_t> * counts = nullptr)
{
  itk::detail::DRRPhiloxRandom   stream(7, chunk, 3);
  itk::detail::DRRPoissonSampler sampler(stream);
  double                         sum = 0.0, sumOfSquares = 0.0, zeros = 0.0;
  for (size_t i = 0; i < n; ++i)
  {
    const uint64_t count = sampler.Sample(mean);
    if (counts)
    {
      counts->push_back(count);
    }
    sum += static_cast<double>(count);
    sumOfSquares += static_cast<double>(count) * static_cast<double>(count);
    zeros += count == 0 ? 1.0 : 0.0;
  }
  Moments m;
  m.Mean = sum / n;
  m.Variance = (sumOfSquares - sum * sum / n) / (n - 1.0);
  m.Zeros = zeros / n;
  return m;
}

ImageType::Pointer
MakeLineIntegrals(const std::vector<float> & values, unsigned int pixelsPerValue)
{
  auto image = ImageType::New();
  image->SetRegions(ImageType::SizeType{ { pixelsPerValue, static_cast<itk::SizeValueType>(values.size()) } });
  image->Allocate();
  for (unsigned int row = 0; row < values.size(); ++row)
  {
    for (unsigned int column = 0; column < pixelsPerValue; ++column)
    {
      image->SetPixel({ { column, row } }, values[row]);
    }
  }
  return image;
}

std::vector<float>
AddNoise(const ImageType * image, double photons, uint64_t seed, unsigned int threads)
{
  auto noise = itk::DRRQuantumNoiseImageFilter<ImageType>::New();
  noise->SetInput(image);
  noise->SetNumberOfPhotons(photons);
  noise->SetSeed(seed);
  noise->SetNumberOfWorkUnits(threads);
  noise->Update();
  const float * out = noise->GetOutput()->GetBufferPointer();
  return std::vector<float>(out, out + noise->GetOutput()->GetBufferedRegion().GetNumberOfPixels());
}
} // namespace

TEST(DRRPoissonSampler, MeanVarianceAndNoPhotonMatchTheClosedForm)
{
  // Both methods (inversion below 10, transformed rejection from 10) and the switch between them.
  const double means[] = { 0.3, 4.0, 9.9, 10.0, 25.0, 200.0, 1e5, 1e9 };
  const size_t n = 40000;
  for (size_t i = 0; i < sizeof(means) / sizeof(means[0]); ++i)
  {
    const double  lambda = means[i];
    const Moments m = DrawCounts(lambda, i, n);
    // Var(mean) = lambda / n; Var(s^2) = (mu4 - sigma^4) / n = (lambda + 2 lambda^2) / n for a Poisson count.
    EXPECT_LE(std::abs(m.Mean - lambda), 5.0 * std::sqrt(lambda / n)) << "mean " << lambda;
    EXPECT_LE(std::abs(m.Variance - lambda), 5.0 * std::sqrt((lambda + 2.0 * lambda * lambda) / n))
      << "variance " << lambda;
    const double p0 = std::exp(-lambda);
    EXPECT_LE(std::abs(m.Zeros - p0), 5.0 * std::sqrt(p0 * (1.0 - p0) / n) + 1e-12) << "P(0) " << lambda;
  }
}

TEST(DRRPoissonSampler, ProbabilityMassAroundTheMeanMatchesThePoissonLaw)
{
  // Each count from 15 to 35 at mean 25 (transformed rejection), as often as exp(-25) 25^k / k! says, within 5 sigma.
  std::vector<uint64_t> counts;
  const size_t          n = 100000;
  DrawCounts(25.0, 99, n, &counts);
  for (uint64_t k = 15; k <= 35; ++k)
  {
    const double p = std::exp(-25.0 + k * std::log(25.0) - std::lgamma(k + 1.0));
    double       seen = 0.0;
    for (uint64_t c : counts)
    {
      seen += c == k ? 1.0 : 0.0;
    }
    EXPECT_LE(std::abs(seen / n - p), 5.0 * std::sqrt(p * (1.0 - p) / n)) << "P(" << k << ")";
  }
}

TEST(DRRQuantumNoiseImageFilter, CountsHaveTheMeanAndVarianceOfI0TimesTheTransmission)
{
  const std::vector<float> lineIntegrals{ 0.0f, 0.5f, 2.0f, 5.0f };
  const unsigned int       pixels = 20000;
  const double             photons = 1000.0;
  const auto               image = MakeLineIntegrals(lineIntegrals, pixels);
  const auto               noisy = AddNoise(image, photons, 11, 2);
  for (size_t r = 0; r < lineIntegrals.size(); ++r)
  {
    const double expected = photons * std::exp(-static_cast<double>(lineIntegrals[r]));
    double       sum = 0.0, sumOfSquares = 0.0;
    for (unsigned int c = 0; c < pixels; ++c)
    {
      // The count the pixel read: I0 exp(-output), a whole number (half a photon for none), to float rounding.
      const double read = photons * std::exp(-static_cast<double>(noisy[r * pixels + c]));
      const double count = read < 0.75 ? 0.0 : std::round(read);
      ASSERT_NEAR(read, count > 0.0 ? count : 0.5, 1e-3 * std::max(1.0, count)) << "row " << r;
      sum += count;
      sumOfSquares += count * count;
    }
    const double mean = sum / pixels;
    const double variance = (sumOfSquares - sum * sum / pixels) / (pixels - 1.0);
    EXPECT_LE(std::abs(mean - expected), 5.0 * std::sqrt(expected / pixels)) << "L " << lineIntegrals[r];
    EXPECT_LE(std::abs(variance - expected), 5.0 * std::sqrt((expected + 2.0 * expected * expected) / pixels))
      << "L " << lineIntegrals[r];
  }
}

TEST(DRRQuantumNoiseImageFilter, SameSeedSameBitsOnOneTwoAndSevenThreads)
{
  const auto image = MakeLineIntegrals({ 0.1f, 1.0f, 3.0f }, 300);
  const auto one = AddNoise(image, 500.0, 4, 1);
  const auto two = AddNoise(image, 500.0, 4, 2);
  const auto seven = AddNoise(image, 500.0, 4, 7);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(float)));
  EXPECT_EQ(0, std::memcmp(one.data(), seven.data(), one.size() * sizeof(float)));
  EXPECT_NE(one, AddNoise(image, 500.0, 5, 1)) << "another seed must draw other counts";
}

TEST(DRRQuantumNoiseImageFilter, RefusesPhotonsOutOfRangeAndLineIntegralsItCannotCount)
{
  const auto image = MakeLineIntegrals({ 1.0f }, 4);
  for (double photons : { 0.0, -1.0, std::nan(""), 2e12, std::numeric_limits<double>::infinity() })
  {
    EXPECT_THROW(AddNoise(image, photons, 0, 1), itk::ExceptionObject) << photons;
  }
  for (float bad : { std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), -40.0f })
  {
    const auto badImage = MakeLineIntegrals({ 1.0f, bad }, 2);
    EXPECT_THROW(AddNoise(badImage, 1e12, 0, 1), itk::ExceptionObject) << bad;
  }
}
