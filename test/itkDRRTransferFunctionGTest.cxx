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
// Tests of DRRTransferFunction (docs/design.md section 6). Expected values are written out by hand:
//   natural: mu = mu_water(E) * max(0, 1 + HU / 1000), HU clamped at -1000;
//   mu_water (1/mm) from NIST XCOM, liquid water: 50 keV 0.02269, 60 keV 0.02059, 80 keV 0.01837, 100 keV 0.01707,
//   150 keV 0.01505 (and the table ends, 10 keV 0.5329, 1000 keV 0.007072), log-log interpolated in between.

#include "gtest/gtest.h"

#include "itkDRRTransferFunction.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace
{
using TransferFunctionType = itk::DRRTransferFunction;
using ModeEnum = TransferFunctionType::ModeEnum;
using PointListType = TransferFunctionType::PointListType;

constexpr double muWater60 = 0.02059; // 1/mm, water at 60 keV

/** Relative tolerance with an absolute floor. */
double
Tolerance(double expected)
{
  return 1e-12 * (1e-3 + std::abs(expected));
}

const double notANumber = std::numeric_limits<double>::quiet_NaN();
const double infinity = std::numeric_limits<double>::infinity();
} // namespace

// ---------------------------------------------------------------------------------------------------------------------
// 1. The natural transfer function at the default 60 keV.

TEST(DRRTransferFunctionNatural, DefaultsAreNaturalAt60keV)
{
  auto tf = TransferFunctionType::New();
  EXPECT_EQ(tf->GetMode(), ModeEnum::Natural);
  EXPECT_EQ(tf->GetEffectiveEnergyInKeV(), 60.0);
  EXPECT_NEAR(tf->GetMuWaterPerMillimeter(), muWater60, 1e-15);
  EXPECT_TRUE(tf->GetPiecewiseLinearPoints().empty());
}

TEST(DRRTransferFunctionNatural, HandValues)
{
  auto tf = TransferFunctionType::New();
  // HU 0 is water: 0.02059 * (1 + 0) = 0.02059.
  EXPECT_NEAR(tf->Evaluate(0.0), 0.02059, Tolerance(0.02059));
  // HU 1000: 0.02059 * (1 + 1) = 0.04118.
  EXPECT_NEAR(tf->Evaluate(1000.0), 0.04118, Tolerance(0.04118));
  // HU -500: 0.02059 * 0.5 = 0.010295.
  EXPECT_NEAR(tf->Evaluate(-500.0), 0.010295, Tolerance(0.010295));
  // HU 3071 (the top of 12-bit CT): 0.02059 * (1 + 3.071) = 0.02059 * 4.071 = 0.08382189.
  EXPECT_NEAR(tf->Evaluate(3071.0), 0.08382189, Tolerance(0.08382189));
  // Air and scanner padding: HU <= -1000 gives exactly 0, never negative.
  EXPECT_EQ(tf->Evaluate(-1000.0), 0.0);
  EXPECT_EQ(tf->Evaluate(-1024.0), 0.0);
  EXPECT_EQ(tf->Evaluate(-2048.0), 0.0);
  EXPECT_EQ(tf->Evaluate(-3024.0), 0.0);
  // Just above air: 0.02059 * (1 - 0.999) = 0.02059e-3.
  EXPECT_NEAR(tf->Evaluate(-999.0), 0.02059e-3, Tolerance(0.02059e-3));
}

TEST(DRRTransferFunctionNatural, NeverNegativeAndNonDecreasing)
{
  auto   tf = TransferFunctionType::New();
  double previous = 0.0;
  for (int hu = -4000; hu <= 4000; ++hu)
  {
    const double mu = tf->Evaluate(hu);
    ASSERT_GE(mu, 0.0) << "HU " << hu;
    ASSERT_GE(mu, previous) << "HU " << hu;
    ASSERT_TRUE(std::isfinite(mu)) << "HU " << hu;
    // The closed form, evaluated by hand for each HU.
    const double expected = hu <= -1000 ? 0.0 : muWater60 * (1.0 + hu / 1000.0);
    ASSERT_NEAR(mu, expected, Tolerance(expected)) << "HU " << hu;
    previous = mu;
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// 2. mu_water from the NIST table.

TEST(DRRTransferFunctionWater, TablePoints)
{
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(50.0), 0.02269, 1e-12);
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(60.0), 0.02059, 1e-12);
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(80.0), 0.01837, 1e-12);
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(100.0), 0.01707, 1e-12);
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(150.0), 0.01505, 1e-12);
  // The ends of the table are inside the valid range: NIST XCOM water, 10 keV 5.329 cm2/g, 1 MeV 0.07072 cm2/g.
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(10.0), 0.5329, 1e-12);
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(1000.0), 0.007072, 1e-12);
}

TEST(DRRTransferFunctionWater, LogLogInterpolation)
{
  // 70 keV between 60 keV (0.02059) and 80 keV (0.01837):
  //   t = ln(70 / 60) / ln(80 / 60) = ln(7/6) / ln(4/3) ~ 0.154151 / 0.287682 ~ 0.535837,
  //   mu = exp((1 - t) ln 0.02059 + t ln 0.01837) = exp(0.464163 * (-3.882950) + 0.535837 * (-3.997036))
  //      ~ exp(-3.944082) ~ 0.019369 /mm.
  const double t = std::log(70.0 / 60.0) / std::log(80.0 / 60.0);
  EXPECT_NEAR(t, 0.535837, 1e-6); // a check on the hand arithmetic above
  const double expected70 = std::exp((1.0 - t) * std::log(0.02059) + t * std::log(0.01837));
  EXPECT_NEAR(expected70, 0.019369, 1e-6);
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(70.0), expected70, Tolerance(expected70));
  // It is not the linear interpolation 0.5 * (0.02059 + 0.01837) = 0.01948.
  EXPECT_GT(std::abs(TransferFunctionType::WaterAttenuationPerMillimeter(70.0) - 0.01948), 1e-5);

  // 120 keV between 100 keV (0.01707) and 150 keV (0.01505): t = ln(1.2) / ln(1.5).
  const double t120 = std::log(1.2) / std::log(1.5);
  const double expected120 = std::exp((1.0 - t120) * std::log(0.01707) + t120 * std::log(0.01505));
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(120.0), expected120, Tolerance(expected120));

  // 55 keV between 50 keV (0.02269) and 60 keV (0.02059): t = ln(1.1) / ln(1.2).
  const double t55 = std::log(1.1) / std::log(1.2);
  const double expected55 = std::exp((1.0 - t55) * std::log(0.02269) + t55 * std::log(0.02059));
  EXPECT_NEAR(TransferFunctionType::WaterAttenuationPerMillimeter(55.0), expected55, Tolerance(expected55));
}

TEST(DRRTransferFunctionWater, MonotoneDecreasingOverTheTable)
{
  double previous = infinity;
  for (double e = 10.0; e <= 1000.0; e *= 1.01)
  {
    const double mu = TransferFunctionType::WaterAttenuationPerMillimeter(e);
    ASSERT_LT(mu, previous) << e << " keV";
    ASSERT_GT(mu, 0.0) << e << " keV";
    previous = mu;
  }
  EXPECT_LT(TransferFunctionType::WaterAttenuationPerMillimeter(1000.0), previous);
}

TEST(DRRTransferFunctionWater, ThrowsOutsideTheTable)
{
  EXPECT_THROW(TransferFunctionType::WaterAttenuationPerMillimeter(9.99), itk::ExceptionObject);
  EXPECT_THROW(TransferFunctionType::WaterAttenuationPerMillimeter(0.0), itk::ExceptionObject);
  EXPECT_THROW(TransferFunctionType::WaterAttenuationPerMillimeter(-60.0), itk::ExceptionObject);
  EXPECT_THROW(TransferFunctionType::WaterAttenuationPerMillimeter(1000.01), itk::ExceptionObject);
  EXPECT_THROW(TransferFunctionType::WaterAttenuationPerMillimeter(notANumber), itk::ExceptionObject);
  EXPECT_THROW(TransferFunctionType::WaterAttenuationPerMillimeter(infinity), itk::ExceptionObject);
}

// ---------------------------------------------------------------------------------------------------------------------
// 3. Setting the energy or mu_water.

TEST(DRRTransferFunctionWater, EffectiveEnergySetsMuWater)
{
  auto tf = TransferFunctionType::New();
  tf->SetEffectiveEnergyInKeV(80.0);
  EXPECT_EQ(tf->GetEffectiveEnergyInKeV(), 80.0);
  EXPECT_NEAR(tf->GetMuWaterPerMillimeter(), 0.01837, 1e-12);
  // HU 500 at 80 keV: 0.01837 * 1.5 = 0.027555.
  EXPECT_NEAR(tf->Evaluate(500.0), 0.027555, Tolerance(0.027555));
  // An energy outside the table throws and changes nothing.
  EXPECT_THROW(tf->SetEffectiveEnergyInKeV(5.0), itk::ExceptionObject);
  EXPECT_THROW(tf->SetEffectiveEnergyInKeV(notANumber), itk::ExceptionObject);
  EXPECT_EQ(tf->GetEffectiveEnergyInKeV(), 80.0);
  EXPECT_NEAR(tf->GetMuWaterPerMillimeter(), 0.01837, 1e-12);
}

TEST(DRRTransferFunctionWater, MuWaterDirectly)
{
  auto tf = TransferFunctionType::New();
  tf->SetMuWaterPerMillimeter(0.02);
  EXPECT_EQ(tf->GetMuWaterPerMillimeter(), 0.02);
  // 0.02 * (1 + 0) = 0.02; 0.02 * (1 + 0.25) = 0.025; 0.02 * (1 - 1) = 0.
  EXPECT_NEAR(tf->Evaluate(0.0), 0.02, Tolerance(0.02));
  EXPECT_NEAR(tf->Evaluate(250.0), 0.025, Tolerance(0.025));
  EXPECT_EQ(tf->Evaluate(-1000.0), 0.0);
  EXPECT_EQ(tf->Evaluate(-3024.0), 0.0);

  EXPECT_THROW(tf->SetMuWaterPerMillimeter(0.0), itk::ExceptionObject);
  EXPECT_THROW(tf->SetMuWaterPerMillimeter(-1.0), itk::ExceptionObject);
  EXPECT_THROW(tf->SetMuWaterPerMillimeter(notANumber), itk::ExceptionObject);
  EXPECT_THROW(tf->SetMuWaterPerMillimeter(infinity), itk::ExceptionObject);
  EXPECT_EQ(tf->GetMuWaterPerMillimeter(), 0.02); // unchanged by the rejected values
}

// ---------------------------------------------------------------------------------------------------------------------
// 4. Piecewise linear.

TEST(DRRTransferFunctionPiecewiseLinear, InterpolatesAndClamps)
{
  auto tf = TransferFunctionType::New();
  EXPECT_EQ(tf->GetMode(), ModeEnum::Natural);
  const PointListType points = { { -1000.0, 0.0 }, { 0.0, 0.02 }, { 1000.0, 0.05 } };
  tf->SetPiecewiseLinearPoints(points);
  EXPECT_EQ(tf->GetMode(), ModeEnum::PiecewiseLinear);
  EXPECT_EQ(tf->GetPiecewiseLinearPoints(), points);
  // The nodes.
  EXPECT_NEAR(tf->Evaluate(-1000.0), 0.0, 1e-15);
  EXPECT_NEAR(tf->Evaluate(0.0), 0.02, Tolerance(0.02));
  EXPECT_NEAR(tf->Evaluate(1000.0), 0.05, Tolerance(0.05));
  // -500: half way from 0 to 0.02 = 0.01. -250: 0.75 of the way = 0.015.
  EXPECT_NEAR(tf->Evaluate(-500.0), 0.01, Tolerance(0.01));
  EXPECT_NEAR(tf->Evaluate(-250.0), 0.015, Tolerance(0.015));
  // 250: 0.02 + 0.25 (0.05 - 0.02) = 0.0275. 900: 0.02 + 0.9 * 0.03 = 0.047.
  EXPECT_NEAR(tf->Evaluate(250.0), 0.0275, Tolerance(0.0275));
  EXPECT_NEAR(tf->Evaluate(900.0), 0.047, Tolerance(0.047));
  // Constant beyond the ends.
  EXPECT_NEAR(tf->Evaluate(-1001.0), 0.0, 1e-15);
  EXPECT_NEAR(tf->Evaluate(-3024.0), 0.0, 1e-15);
  EXPECT_NEAR(tf->Evaluate(1000.5), 0.05, Tolerance(0.05));
  EXPECT_NEAR(tf->Evaluate(1e9), 0.05, Tolerance(0.05));
}

TEST(DRRTransferFunctionPiecewiseLinear, SinglePointIsConstant)
{
  auto tf = TransferFunctionType::New();
  tf->SetPiecewiseLinearPoints({ { 100.0, 0.03 } });
  EXPECT_NEAR(tf->Evaluate(-5000.0), 0.03, Tolerance(0.03));
  EXPECT_NEAR(tf->Evaluate(100.0), 0.03, Tolerance(0.03));
  EXPECT_NEAR(tf->Evaluate(5000.0), 0.03, Tolerance(0.03));
}

TEST(DRRTransferFunctionPiecewiseLinear, PointByPointEqualsTheWholeList)
{
  // The wrapping-friendly form: one point at a time, checked against the last.
  auto whole = TransferFunctionType::New();
  whole->SetPiecewiseLinearPoints({ { -1000.0, 0.0 }, { 0.0, 0.02 }, { 1000.0, 0.05 } });
  auto       pointwise = TransferFunctionType::New();
  const auto before = pointwise->GetMTime();
  pointwise->AddPiecewiseLinearPoint(-1000.0, 0.0);
  pointwise->AddPiecewiseLinearPoint(0.0, 0.02);
  pointwise->AddPiecewiseLinearPoint(1000.0, 0.05);
  EXPECT_GT(pointwise->GetMTime(), before);
  EXPECT_EQ(pointwise->GetMode(), ModeEnum::PiecewiseLinear);
  EXPECT_EQ(pointwise->GetNumberOfPiecewiseLinearPoints(), 3u);
  EXPECT_EQ(pointwise->GetPiecewiseLinearPoints(), whole->GetPiecewiseLinearPoints());
  for (double hu : { -3000.0, -400.0, 250.0, 5000.0 })
  {
    EXPECT_EQ(pointwise->Evaluate(hu), whole->Evaluate(hu)) << hu;
  }
  // A value not after the last, or a negative mu, is refused and leaves the function as it was.
  EXPECT_THROW(pointwise->AddPiecewiseLinearPoint(500.0, 0.1), itk::ExceptionObject);
  EXPECT_THROW(pointwise->AddPiecewiseLinearPoint(2000.0, -0.1), itk::ExceptionObject);
  EXPECT_EQ(pointwise->GetNumberOfPiecewiseLinearPoints(), 3u);
  pointwise->ClearPiecewiseLinearPoints();
  EXPECT_EQ(pointwise->GetNumberOfPiecewiseLinearPoints(), 0u);
  EXPECT_THROW(pointwise->Evaluate(0.0), itk::ExceptionObject);
}

TEST(DRRTransferFunctionPiecewiseLinear, RejectsBadPoints)
{
  auto tf = TransferFunctionType::New();
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({}), itk::ExceptionObject);
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({ { 0.0, 0.1 }, { 0.0, 0.2 } }), itk::ExceptionObject); // equal values
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({ { 0.0, 0.1 }, { 100.0, 0.2 }, { 50.0, 0.3 } }),
               itk::ExceptionObject);                                                                      // decreasing
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({ { 0.0, 0.1 }, { 100.0, -0.01 } }), itk::ExceptionObject);    // mu < 0
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({ { 0.0, 0.1 }, { notANumber, 0.2 } }), itk::ExceptionObject); // NaN value
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({ { 0.0, notANumber } }), itk::ExceptionObject);               // NaN mu
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({ { 0.0, infinity } }), itk::ExceptionObject);                // infinite mu
  EXPECT_THROW(tf->SetPiecewiseLinearPoints({ { -infinity, 0.0 }, { 0.0, 0.1 } }), itk::ExceptionObject); // infinite
  // A rejected list changes neither the mode nor the points.
  EXPECT_EQ(tf->GetMode(), ModeEnum::Natural);
  EXPECT_TRUE(tf->GetPiecewiseLinearPoints().empty());
  EXPECT_NEAR(tf->Evaluate(0.0), muWater60, Tolerance(muWater60));
}

// ---------------------------------------------------------------------------------------------------------------------
// 5. Identity.

TEST(DRRTransferFunctionIdentity, ReturnsTheInput)
{
  auto tf = TransferFunctionType::New();
  tf->SetMode(ModeEnum::Identity);
  EXPECT_EQ(tf->GetMode(), ModeEnum::Identity);
  EXPECT_EQ(tf->Evaluate(0.0), 0.0);
  EXPECT_EQ(tf->Evaluate(0.0123), 0.0123);
  EXPECT_EQ(tf->Evaluate(2.5), 2.5);
  EXPECT_EQ(tf->Evaluate(-1500.0), -1500.0); // no clamping: the filters reject negative mu
  EXPECT_EQ(tf->Evaluate(-0.5), -0.5);
}

// ---------------------------------------------------------------------------------------------------------------------
// 6. Air threshold.

TEST(DRRTransferFunctionAirThreshold, BelowThresholdIsAir)
{
  auto tf = TransferFunctionType::New();
  EXPECT_EQ(tf->GetAirThreshold(), -infinity);
  tf->SetAirThreshold(-500.0);
  EXPECT_EQ(tf->GetAirThreshold(), -500.0);
  EXPECT_EQ(tf->Evaluate(-600.0), 0.0);
  EXPECT_EQ(tf->Evaluate(-500.5), 0.0);
  // -400 is above the threshold: the natural value 0.02059 * 0.6 = 0.012354.
  EXPECT_NEAR(tf->Evaluate(-400.0), 0.012354, Tolerance(0.012354));
  // "Strictly below" is air: -500 itself keeps its natural value 0.02059 * 0.5 = 0.010295.
  EXPECT_NEAR(tf->Evaluate(-500.0), 0.010295, Tolerance(0.010295));
  EXPECT_NEAR(tf->Evaluate(1000.0), 0.04118, Tolerance(0.04118));

  // The threshold applies in the other modes too, in input units.
  tf->SetMode(ModeEnum::Identity);
  tf->SetAirThreshold(0.001);
  EXPECT_EQ(tf->Evaluate(0.0005), 0.0);
  EXPECT_EQ(tf->Evaluate(0.002), 0.002);
  tf->SetPiecewiseLinearPoints({ { -1000.0, 0.0 }, { 0.0, 0.02 }, { 1000.0, 0.05 } });
  tf->SetAirThreshold(-100.0);
  EXPECT_EQ(tf->Evaluate(-200.0), 0.0);
  // -50: 0.02 * (1 - 50 / 1000) = 0.019.
  EXPECT_NEAR(tf->Evaluate(-50.0), 0.019, Tolerance(0.019));
}

// ---------------------------------------------------------------------------------------------------------------------
// 7. Modified time and printing.

TEST(DRRTransferFunctionModifiedTime, EverySetterModifies)
{
  auto tf = TransferFunctionType::New();
  auto last = tf->GetMTime();
  auto expectModified = [&](const char * what) {
    const auto now = tf->GetMTime();
    EXPECT_GT(now, last) << what;
    last = now;
  };
  tf->SetEffectiveEnergyInKeV(80.0);
  expectModified("SetEffectiveEnergyInKeV");
  tf->SetMuWaterPerMillimeter(0.03);
  expectModified("SetMuWaterPerMillimeter");
  tf->SetAirThreshold(-900.0);
  expectModified("SetAirThreshold");
  tf->SetPiecewiseLinearPoints({ { 0.0, 0.0 }, { 1.0, 1.0 } });
  expectModified("SetPiecewiseLinearPoints");
  tf->SetMode(ModeEnum::Identity);
  expectModified("SetMode");
  tf->SetEffectiveEnergyInKeV(100.0);
  expectModified("SetEffectiveEnergyInKeV again");
  // A rejected value does not count as a modification.
  EXPECT_THROW(tf->SetMuWaterPerMillimeter(-1.0), itk::ExceptionObject);
  EXPECT_EQ(tf->GetMTime(), last);
}

TEST(DRRTransferFunctionPrint, MentionsTheParameters)
{
  auto tf = TransferFunctionType::New();
  tf->SetEffectiveEnergyInKeV(100.0);
  std::ostringstream os;
  tf->Print(os);
  const std::string text = os.str();
  EXPECT_NE(text.find("MuWaterPerMillimeter"), std::string::npos) << text;
  EXPECT_NE(text.find("0.01707"), std::string::npos) << text;
  EXPECT_NE(text.find("AirThreshold"), std::string::npos) << text;
}
