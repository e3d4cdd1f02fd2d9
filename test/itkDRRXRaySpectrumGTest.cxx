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
// X-ray spectra (issue 16, item 2): DRRXRaySpectrum's file format and bad inputs, and Kramers' law.
#include "itkDRRXRaySpectrum.h"

#include "gtest/gtest.h"

#include <xraylib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace
{
std::string
WriteSpectrum(const std::string & text)
{
  static const std::filesystem::path directory =
    std::filesystem::temp_directory_path() / ("PointBasedDRRXRaySpectrumGTest-" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  const std::string path = (directory / "spectrum.txt").string();
  std::ofstream     file(path);
  file << text;
  return path;
}

std::string
ReadError(const std::string & text)
{
  auto spectrum = itk::DRRXRaySpectrum::New();
  try
  {
    spectrum->ReadFile(WriteSpectrum(text));
  }
  catch (const itk::ExceptionObject & e)
  {
    return e.GetDescription();
  }
  return "";
}
} // namespace

TEST(DRRXRaySpectrum, ReadsTwoColumnFiles)
{
  auto spectrum = itk::DRRXRaySpectrum::New();
  spectrum->ReadFile(WriteSpectrum("# energy_keV fluence\n20.5 100\n\n30.5, 300 # comma\n40.5\t0\n"));
  ASSERT_EQ(spectrum->GetNumberOfBins(), 3u);
  EXPECT_EQ(spectrum->GetEnergies()[1], 30.5);
  EXPECT_EQ(spectrum->GetFluence()[1], 300.0);
  EXPECT_DOUBLE_EQ(spectrum->GetMeanEnergyInKeV(), (20.5 * 100 + 30.5 * 300) / 400.0);
  std::ostringstream print;
  spectrum->Print(print);
  EXPECT_NE(print.str().find("MeanEnergyInKeV"), std::string::npos);
}

TEST(DRRXRaySpectrum, BadFilesThrowNamingTheLine)
{
  struct Case
  {
    const char * Text;
    const char * Expected;
  };
  const Case cases[] = {
    { "20 1\n30 -1\n", "line 2: fluence -1 at 30 keV must be finite and >= 0" },
    { "20 1\n# c\n15 1\n", "line 3: energy 15 keV is not above the previous bin's 20 keV" },
    { "20 1\n20 1\n", "line 2: energy 20 keV is not above the previous bin's 20 keV" },
    { "0.5 1\n", "line 1: energy 0.5 keV is outside 1 to 800 keV" },
    { "20 1\n900 1\n", "line 2: energy 900 keV is outside 1 to 800 keV" },
    { "20 1\nnan 1\n", "line 2: expected two finite numbers" },
    { "20 1\n30 nan\n", "line 2: expected two finite numbers" },
    { "20 1\n30 1 5\n", "line 2: expected two finite numbers" },
    { "20 1\n30\n", "line 2: expected two finite numbers" },
    { "# nothing\n\n", "has no bin (empty)" },
    { "20 0\n30 0\n", "has no photons" },
  };
  for (const Case & c : cases)
  {
    const std::string error = ReadError(c.Text);
    EXPECT_NE(error.find(c.Expected), std::string::npos) << "file:\n" << c.Text << "error: " << error;
  }
  auto spectrum = itk::DRRXRaySpectrum::New();
  EXPECT_THROW(spectrum->ReadFile("/nonexistent/spectrum.txt"), itk::ExceptionObject);
  EXPECT_THROW(spectrum->GetMeanEnergyInKeV(), itk::ExceptionObject);
  EXPECT_THROW(spectrum->SetSpectrum({ 20.0, 30.0 }, { 1.0 }), itk::ExceptionObject);
  EXPECT_THROW(spectrum->SetSpectrum({}, {}), itk::ExceptionObject);
  EXPECT_THROW(spectrum->SetKramers(0.5), itk::ExceptionObject);
  EXPECT_THROW(spectrum->SetKramers(120.0, -1.0), itk::ExceptionObject);
  EXPECT_THROW(spectrum->SetKramers(120.0, 2.5, 0.0), itk::ExceptionObject);
  EXPECT_THROW(spectrum->SetKramers(120.0, std::nan("")), itk::ExceptionObject);
}

TEST(DRRXRaySpectrum, KramersShapeVanishesAtTheTubeVoltage)
{
  auto         spectrum = itk::DRRXRaySpectrum::New();
  const double kVp = 120.0;
  spectrum->SetKramers(kVp, 2.5, 1.0);
  const auto & energies = spectrum->GetEnergies();
  const auto & fluence = spectrum->GetFluence();
  ASSERT_EQ(spectrum->GetNumberOfBins(), 119u); // centres 1.5 .. 119.5 keV (0.5 keV is below 1 keV)
  EXPECT_EQ(energies.front(), 1.5);
  EXPECT_EQ(energies.back(), kVp - 0.5);
  // N(E) = (kVp - E) / E exp(-(mu/rho)_Al(E) 2.699 g/cm^3 0.25 cm), independently with xraylib.
  for (size_t i = 0; i < energies.size(); ++i)
  {
    const double e = energies[i];
    const double expected = (kVp - e) / e * std::exp(-CS_Total_CP("Al", e, nullptr) * 2.699 * 0.25);
    EXPECT_NEAR(fluence[i], expected, 1e-12 * (1.0 + expected)) << e;
  }
  // Zero at kVp: the last bin holds the fluence of kVp - 0.5 keV, a hundredth of the peak's or less.
  const double peak = *std::max_element(fluence.begin(), fluence.end());
  EXPECT_LT(fluence.back(), 0.01 * peak);
  // The filter removes the lowest energies.
  EXPECT_LT(fluence[5] /* 6.5 keV */, 1e-6 * peak);
}

TEST(DRRXRaySpectrum, AluminiumHardensTheBeam)
{
  auto   spectrum = itk::DRRXRaySpectrum::New();
  double previous = 0.0;
  for (const double aluminium : { 0.0, 1.0, 2.5, 5.0, 10.0 })
  {
    spectrum->SetKramers(120.0, aluminium, 0.5);
    const double mean = spectrum->GetMeanEnergyInKeV();
    std::cout << "Kramers 120 kVp, " << aluminium << " mm Al: mean energy " << mean << " keV" << std::endl;
    EXPECT_GT(mean, previous) << aluminium;
    previous = mean;
  }
}

TEST(DRRXRaySpectrum, UnfilteredKramersMeanEnergyMatchesTheClosedForm)
{
  // Bins of 0.01 keV from 1 keV (the lowest kept) to kVp: mean = int_1^kVp (kVp - E) dE / int_1^kVp (kVp - E) / E dE
  // = (kVp - 1)^2 / 2 / (kVp ln kVp - (kVp - 1)).
  auto spectrum = itk::DRRXRaySpectrum::New();
  for (const double kVp : { 70.0, 120.0 })
  {
    spectrum->SetKramers(kVp, 0.0, 0.01);
    const double closedForm = (kVp - 1.0) * (kVp - 1.0) / 2.0 / (kVp * std::log(kVp) - (kVp - 1.0));
    EXPECT_NEAR(spectrum->GetMeanEnergyInKeV() / closedForm, 1.0, 1e-5) << kVp;
    std::cout << kVp << " kVp unfiltered: mean " << spectrum->GetMeanEnergyInKeV() << " keV, closed form " << closedForm
              << " keV" << std::endl;
  }
}
