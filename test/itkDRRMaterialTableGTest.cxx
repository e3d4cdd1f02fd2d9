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
// Materials (issue 16, item 2): xraylib against the module's NIST water table, DRRMaterialTable (the default table,
// the file format and every bad input), and the Materials mode of DRRTransferFunction.
#include "itkDRRMaterialTable.h"
#include "itkDRRTransferFunction.h"

#include "gtest/gtest.h"

#include <xraylib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

namespace
{
const char * const Air = "Air, Dry (near sea level)";
const char * const Soft = "Tissue, Soft (ICRP)";
const char * const Bone = "Bone, Cortical (ICRP)";

// A file of the given text in a directory of this process; removed with the directory at exit.
std::string
WriteFile(const std::string & name, const std::string & text)
{
  static const std::filesystem::path directory =
    std::filesystem::temp_directory_path() / ("PointBasedDRRMaterialTableGTest-" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  const std::string path = (directory / name).string();
  std::ofstream     file(path);
  file << text;
  return path;
}

// The description of the exception ReadFile() throws on the text, or "" if none.
std::string
ReadError(const std::string & text)
{
  auto table = itk::DRRMaterialTable::New();
  try
  {
    table->ReadFile(WriteFile("bad.txt", text));
  }
  catch (const itk::ExceptionObject & e)
  {
    return e.GetDescription();
  }
  return "";
}

double
XraylibWater(double energyInKeV)
{
  return CS_Total_CP("Water, Liquid", energyInKeV, nullptr); // cm^2/g
}
} // namespace

TEST(DRRMaterialTable, XraylibWaterMatchesTheNISTTableOfTheTransferFunction)
{
  // The module's table is NIST XCOM (total with coherent scattering), xraylib's CS_Total_CP the same physics.
  for (const double energy : { 50.0, 60.0, 80.0, 100.0, 150.0 })
  {
    const double nist = itk::DRRTransferFunction::WaterAttenuationPerMillimeter(energy) * 10.0; // cm^2/g at 1 g/cm^3
    const double xraylib = itk::DRRMaterialTable::MassAttenuationInCm2PerGram("Water, Liquid", energy);
    EXPECT_EQ(xraylib, XraylibWater(energy));
    EXPECT_NEAR(xraylib / nist, 1.0, 0.01) << energy << " keV";
    std::cout << "water " << energy << " keV: xraylib " << xraylib << " cm^2/g, NIST table " << nist
              << " cm^2/g, ratio " << xraylib / nist << std::endl;
  }
  // A formula works as well: H2O within 0.1 % of the NIST compound.
  EXPECT_NEAR(itk::DRRMaterialTable::MassAttenuationInCm2PerGram("H2O", 60.0) / XraylibWater(60.0), 1.0, 1e-3);
}

TEST(DRRMaterialTable, XraylibErrorsBecomeExceptionsNamingTheMaterial)
{
  try
  {
    itk::DRRMaterialTable::MassAttenuationInCm2PerGram("Unobtainium", 60.0);
    FAIL() << "no exception";
  }
  catch (const itk::ExceptionObject & e)
  {
    EXPECT_NE(std::string(e.GetDescription()).find("'Unobtainium'"), std::string::npos) << e.GetDescription();
  }
  EXPECT_THROW(itk::DRRMaterialTable::MassAttenuationInCm2PerGram("Water, Liquid", 900.0), itk::ExceptionObject);
  EXPECT_THROW(itk::DRRMaterialTable::MassAttenuationInCm2PerGram("Water, Liquid", 0.5), itk::ExceptionObject);
  EXPECT_THROW(itk::DRRMaterialTable::MassAttenuationInCm2PerGram("Water, Liquid", std::nan("")), itk::ExceptionObject);
  auto table = itk::DRRMaterialTable::New();
  EXPECT_THROW(table->AddMaterial(-1.0, 1.0, "Lung Tissue (ICRP)", 0.3, 0.3), itk::ExceptionObject); // "Lung (ICRP)"
  EXPECT_NO_THROW(table->AddMaterial(-1.0, 1.0, "Lung (ICRP)", 0.3, 0.3));
}

TEST(DRRMaterialTable, DefaultIsDeepDRRsThreeMaterials)
{
  auto table = itk::DRRMaterialTable::New();
  table->SetDefault();
  ASSERT_EQ(table->GetNumberOfMaterials(), 3u);
  EXPECT_EQ(table->GetMaterialName(0), Air);
  EXPECT_EQ(table->GetMaterialName(1), Soft);
  EXPECT_EQ(table->GetMaterialName(2), Bone);
  EXPECT_TRUE(table->IsComplete());
  // Thresholds -800 and 350 HU.
  EXPECT_EQ(table->GetMaterialIndex(-3024.0), 0u);
  EXPECT_EQ(table->GetMaterialIndex(-800.001), 0u);
  EXPECT_EQ(table->GetMaterialIndex(-800.0), 1u);
  EXPECT_EQ(table->GetMaterialIndex(349.999), 1u);
  EXPECT_EQ(table->GetMaterialIndex(350.0), 2u);
  EXPECT_EQ(table->GetMaterialIndex(1e6), 2u);
  // DeepDRR's density, max(0, min(1.030 + 0.001029 HU, 1.030 + 0.0005886 HU)), held below -1000 and above 3000 HU.
  for (const double hu : { -1000.0, -900.0, -800.0, -500.0, -1.0, 0.0, 1.0, 100.0, 350.0, 1000.0, 3000.0 })
  {
    EXPECT_NEAR(table->GetDensity(hu), std::min(1.030 + 0.001029 * hu, 1.030 + 0.0005886 * hu), 1e-12) << hu;
  }
  EXPECT_NEAR(table->GetDensity(-3024.0), 0.001, 1e-12);
  EXPECT_NEAR(table->GetDensity(5000.0), 1.030 + 0.0005886 * 3000.0, 1e-12);
  // Continuous at every row boundary.
  for (unsigned int r = 1; r < table->GetNumberOfRows(); ++r)
  {
    EXPECT_DOUBLE_EQ(table->GetRow(r - 1).DensityAtUpperInGramsPerCubicCentimetre,
                     table->GetRow(r).DensityAtLowerInGramsPerCubicCentimetre)
      << r;
  }
  // Soft tissue of 0 HU: ~1 g/cm^3 and ~water's mu (DeepDRR's 1.030 g/cm^3: +1.6 % at 60 keV).
  const double water = itk::DRRTransferFunction::WaterAttenuationPerMillimeter(60.0);
  EXPECT_NEAR(table->GetDensity(0.0), 1.0, 0.031);
  EXPECT_NEAR(table->GetMuPerMillimeter(0.0, 60.0) / water, 1.0, 0.02);
  EXPECT_DOUBLE_EQ(table->GetMuPerMillimeter(0.0, 60.0),
                   1.030 * CS_Total_CP(Soft, 60.0, nullptr) / 10.0); // density x mass attenuation / 10
  EXPECT_DOUBLE_EQ(table->GetMassAttenuation(2, 80.0), CS_Total_CP(Bone, 80.0, nullptr));
  std::cout << "HU 0: " << table->GetDensity(0.0) << " g/cm^3, mu(60 keV) " << table->GetMuPerMillimeter(0.0, 60.0)
            << " /mm, water " << water << " /mm" << std::endl;
  EXPECT_THROW(table->GetMaterialIndex(std::nan("")), itk::ExceptionObject);
  EXPECT_THROW(table->GetMassAttenuation(3, 60.0), itk::ExceptionObject);
  EXPECT_THROW(table->GetMaterialName(3), itk::ExceptionObject);
}

TEST(DRRMaterialTable, ReadsTheDocumentedFileFormat)
{
  const std::string text = "# lower upper material density_lower density_upper\n"
                           "-inf, -1000, \"Air, Dry (near sea level)\", 0.001, 0.001   # comma-separated\n"
                           "\n"
                           "-1000  -100  \"Adipose Tissue (ICRP)\"  0.5  0.92\n"
                           "-100   200   H2O  0.92  1.1\n"
                           "200    +inf  Ca  1.55  1.55\n";
  auto              table = itk::DRRMaterialTable::New();
  table->SetDefault();
  table->ReadFile(WriteFile("good.txt", text));
  ASSERT_EQ(table->GetNumberOfRows(), 4u);
  ASSERT_EQ(table->GetNumberOfMaterials(), 4u);
  EXPECT_EQ(table->GetMaterialName(0), Air);
  EXPECT_EQ(table->GetMaterialName(1), "Adipose Tissue (ICRP)");
  EXPECT_EQ(table->GetMaterialName(2), "H2O");
  EXPECT_EQ(table->GetMaterialName(3), "Ca");
  EXPECT_EQ(table->GetMaterialIndex(50.0), 2u);
  EXPECT_NEAR(table->GetDensity(50.0), 0.92 + (1.1 - 0.92) * 150.0 / 300.0, 1e-12);
  EXPECT_NEAR(table->GetDensity(-550.0), 0.71, 1e-12);
  EXPECT_EQ(table->GetDensity(1e9), 1.55);
  EXPECT_EQ(table->GetRow(0).LowerHU, -std::numeric_limits<double>::infinity());
}

TEST(DRRMaterialTable, BadFilesThrowNamingTheLine)
{
  const std::string head = "-inf -1000 Air 0.001 0.001\n"; // "Air" is no formula: only in the unknown-name case
  struct Case
  {
    const char * Text;
    const char * Expected;
  };
  const Case cases[] = {
    { "-inf 0 H2O 1 1\n0 inf H2O 1\n", "line 2: expected 5 fields" },
    { "-inf 0 H2O 1 1\n0 inf H2O 1 x1\n", "line 2: the density at the upper HU 'x1' is not a number" },
    { "-inf 0 H2O 1 1\nnan inf H2O 1 1\n", "line 2: the lower HU 'nan' is not a number" },
    { "-inf 0 H2O 1 1\n0 inf H2O nan nan\n", "line 2: the density at the lower HU 'nan' is not a number" },
    { "-inf 0 H2O 1 1\n-5 inf H2O 1 1\n",
      "line 2: material row [-5, inf) HU: rows must be sorted and contiguous, it "
      "overlaps" },
    { "-inf 0 H2O 1 1\n5 inf H2O 1 1\n",
      "line 2: material row [5, inf) HU: rows must be sorted and contiguous, it "
      "leaves a gap" },
    { "-inf 0 H2O 1 1\n0 -10 H2O 1 1\n", "line 2: material row [0, -10) HU: the upper bound must be above" },
    { "-inf 0 H2O 1 1\n0 10 H2O -1 1\n10 inf H2O 1 1\n",
      "line 2: material row [0, 10) HU: densities must be finite "
      "and >= 0" },
    { "-inf 0 H2O 1 1\n0 inf Unobtainium 1 1\n", "line 2: " },
    { "-inf 0 H2O 1 1\n0 inf \"Water, Liquid 1 1\n", "line 2: unterminated quote" },
    { "-inf 0 H2O 0.5 1\n0 inf H2O 1 1\n",
      "line 1: material row [-inf, 0) HU: a row with an infinite bound has a "
      "constant density" },
    { "-inf 0 H2O 1 1\n0 100 H2O 1 1.2\n", "line 2: the rows must cover every HU" },
    { "-100 0 H2O 1 1\n0 inf H2O 1 1\n", "line 2: the rows must cover every HU" },
    { "# nothing\n", "has no row" },
  };
  for (const Case & c : cases)
  {
    const std::string error = ReadError(c.Text);
    EXPECT_NE(error.find(c.Expected), std::string::npos) << "file:\n" << c.Text << "error: " << error;
  }
  EXPECT_NE(ReadError("-inf 0 H2O 1 1\n0 inf Unobtainium 1 1\n").find("'Unobtainium'"), std::string::npos);
  EXPECT_NE(ReadError(head + "-1000 inf H2O 1 1\n").find("'Air'"), std::string::npos);
  // A missing file.
  auto table = itk::DRRMaterialTable::New();
  try
  {
    table->ReadFile("/nonexistent/materials.txt");
    FAIL() << "no exception";
  }
  catch (const itk::ExceptionObject & e)
  {
    EXPECT_NE(std::string(e.GetDescription()).find("cannot open the material table file '/nonexistent/materials.txt'"),
              std::string::npos)
      << e.GetDescription();
  }
  // A failed read leaves the table as it was.
  table->SetDefault();
  EXPECT_THROW(table->ReadFile(WriteFile("gap.txt", "-inf 0 H2O 1 1\n5 inf H2O 1 1\n")), itk::ExceptionObject);
  EXPECT_EQ(table->GetNumberOfMaterials(), 3u);
}

TEST(DRRTransferFunction, MaterialsModeIsTheTablesMuAtTheEffectiveEnergy)
{
  auto table = itk::DRRMaterialTable::New();
  table->SetDefault();
  auto transfer = itk::DRRTransferFunction::New();
  EXPECT_EQ(transfer->GetMaterialIndex(500.0), -1); // Natural
  transfer->SetMaterialTable(table);
  EXPECT_EQ(transfer->GetMode(), itk::PointBasedDRREnums::TransferFunction::Materials);
  std::ostringstream name;
  name << transfer->GetMode();
  EXPECT_EQ(name.str(), "Materials");
  for (const double hu : { -3024.0, -1000.0, -850.0, -300.0, 0.0, 200.0, 349.0, 350.0, 1200.0, 4000.0 })
  {
    EXPECT_DOUBLE_EQ(transfer->Evaluate(hu), table->GetMuPerMillimeter(hu, 60.0)) << hu;
    EXPECT_EQ(transfer->GetMaterialIndex(hu), static_cast<int>(table->GetMaterialIndex(hu))) << hu;
  }
  transfer->SetEffectiveEnergyInKeV(100.0);
  EXPECT_DOUBLE_EQ(transfer->Evaluate(1200.0), table->GetMuPerMillimeter(1200.0, 100.0));
  // The table changed after it was set: the transfer function follows it.
  table->ReadFile(WriteFile("one.txt", "-inf inf H2O 1 1\n"));
  EXPECT_DOUBLE_EQ(transfer->Evaluate(1200.0), CS_Total_CP("H2O", 100.0, nullptr) / 10.0);
  EXPECT_EQ(transfer->GetMaterialIndex(1200.0), 0);
  EXPECT_THROW(transfer->SetEffectiveEnergyInKeV(900.0), itk::ExceptionObject); // above xraylib's range
  EXPECT_THROW(transfer->SetMaterialTable(nullptr), itk::ExceptionObject);
  auto partial = itk::DRRMaterialTable::New();
  partial->AddMaterial(-1000.0, 0.0, "H2O", 1.0, 1.0);
  EXPECT_THROW(transfer->SetMaterialTable(partial), itk::ExceptionObject);
  auto noTable = itk::DRRTransferFunction::New();
  noTable->SetMode(itk::PointBasedDRREnums::TransferFunction::Materials);
  EXPECT_THROW(noTable->Evaluate(0.0), itk::ExceptionObject);
  transfer->SetMode(itk::PointBasedDRREnums::TransferFunction::Natural);
  EXPECT_EQ(transfer->GetMaterialIndex(1200.0), -1);
  std::ostringstream print;
  transfer->Print(print);
  EXPECT_NE(print.str().find("MaterialTable"), std::string::npos);
}
