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
// The attenuation model held once (issue 27): 16-bit keys read in place with a table of mu per key, residual volumes
// computed from rows, and the stratified sampler's brick sums read from them.
#include "itkDRRAttenuationVolume.h"
#include "itkDRRControlVariate.h"
#include "itkDRRStratifiedSampler.h"
#include "itkDRRTransferFunction.h"
#include "itkImportImageContainer.h"
#include "itkPlatformMultiThreader.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <mutex>
#include <random>
#include <string>
#include <vector>

namespace
{
using TransferSetup = std::function<void(itk::DRRTransferFunction *)>;

/** The transfer functions the lookup must reproduce, named. */
std::vector<std::pair<std::string, TransferSetup>>
TransferFunctions()
{
  return {
    { "natural 60 keV", [](itk::DRRTransferFunction *) {} },
    { "natural 120 keV, air below -900 HU",
      [](itk::DRRTransferFunction * t) {
        t->SetEffectiveEnergyInKeV(120.0);
        t->SetAirThreshold(-900.0);
      } },
    { "mu_water 0.0173 /mm", [](itk::DRRTransferFunction * t) { t->SetMuWaterPerMillimeter(0.0173); } },
    { "piecewise linear",
      [](itk::DRRTransferFunction * t) {
        t->SetMode(itk::DRRTransferFunction::ModeEnum::PiecewiseLinear);
        t->SetPiecewiseLinearPoints({ { -1000.0, 0.0 }, { 0.0, 0.02 }, { 1000.0, 0.05 }, { 3000.0, 0.11 } });
      } },
  };
}

/** A 64 x 32 x 32 volume holding every int16 value once, shuffled. */
std::vector<int16_t>
EveryInt16Value()
{
  std::vector<int16_t> values(65536);
  for (size_t v = 0; v < values.size(); ++v)
  {
    values[v] = static_cast<int16_t>(static_cast<int32_t>(v) - 32768);
  }
  std::mt19937_64 random(27);
  std::shuffle(values.begin(), values.end(), random);
  return values;
}

const itk::DRRAttenuationVolume::SizeType everySize{ { 64, 32, 32 } };

/** Uniformly random HU in [lowest, highest] on a grid, from a fixed seed. */
std::vector<int16_t>
RandomHU(const itk::DRRAttenuationVolume::SizeType & size, int lowest, int highest, unsigned int seed)
{
  std::vector<int16_t>               values(size[0] * size[1] * size[2]);
  std::mt19937                       random(seed);
  std::uniform_int_distribution<int> hu(lowest, highest);
  for (auto & value : values)
  {
    value = static_cast<int16_t>(hu(random));
  }
  return values;
}

/** A volume of int16 HU under the natural transfer function, read in place (its values must outlive it). */
itk::DRRAttenuationVolume::Pointer
BuildInPlace(const std::vector<int16_t> & values, const itk::DRRAttenuationVolume::SizeType & size)
{
  auto transfer = itk::DRRTransferFunction::New();
  auto owner = itk::ImportImageContainer<itk::SizeValueType, int16_t>::New();
  auto volume = itk::DRRAttenuationVolume::New();
  volume->Build(values.data(), size, *transfer, nullptr, owner.GetPointer());
  return volume;
}

/** Every voxel's mu read by rows (FillMuRow()) and by boxes (FillMuBox()). */
std::vector<float>
ReadByRows(const itk::DRRAttenuationVolume & volume)
{
  const auto &       size = volume.GetSize();
  std::vector<float> mu(volume.GetNumberOfVoxels());
  for (uint64_t k = 0; k < size[2]; ++k)
  {
    for (uint64_t j = 0; j < size[1]; ++j)
    {
      volume.FillMuRow(0, j, k, size[0], mu.data() + size[0] * (j + size[1] * k));
    }
  }
  return mu;
}

std::vector<float>
ReadByBoxes(const itk::DRRAttenuationVolume & volume, uint64_t side)
{
  const auto &       size = volume.GetSize();
  std::vector<float> mu(volume.GetNumberOfVoxels());
  std::vector<float> box(side * side * side);
  for (uint64_t k = 0; k < size[2]; k += side)
  {
    for (uint64_t j = 0; j < size[1]; j += side)
    {
      for (uint64_t i = 0; i < size[0]; i += side)
      {
        const uint64_t ni = std::min(side, size[0] - i), nj = std::min(side, size[1] - j),
                       nk = std::min(side, size[2] - k);
        volume.FillMuBox(i, j, k, ni, nj, nk, box.data());
        for (uint64_t z = 0; z < nk; ++z)
        {
          for (uint64_t y = 0; y < nj; ++y)
          {
            for (uint64_t x = 0; x < ni; ++x)
            {
              mu[i + x + size[0] * (j + y + size[1] * (k + z))] = box[x + ni * (y + nj * z)];
            }
          }
        }
      }
    }
  }
  return mu;
}

/** The first voxel where two mu images differ, as text (empty if none). */
std::string
FirstDifference(const std::vector<float> & a, const float * b, const std::vector<int16_t> * values = nullptr)
{
  for (size_t v = 0; v < a.size(); ++v)
  {
    if (std::memcmp(&a[v], &b[v], sizeof(float)) != 0)
    {
      return "voxel " + std::to_string(v) + (values ? " (value " + std::to_string((*values)[v]) + ")" : "") + ": " +
             std::to_string(a[v]) + " vs " + std::to_string(b[v]);
    }
  }
  return {};
}
} // namespace

// The table of mu per key is the transfer function's float mu for every int16 value, read in place (the pixel
// container kept), copied to keys, or given as float values: the same bits by rows, boxes and GetMuBuffer().
TEST(DRRAttenuationVolume, KeyLookupEqualsTheTransferFunctionForEveryInt16Value)
{
  const std::vector<int16_t> values = EveryInt16Value();
  std::vector<float>         asFloat(values.begin(), values.end());
  for (const auto & named : TransferFunctions())
  {
    auto transfer = itk::DRRTransferFunction::New();
    named.second(transfer);
    std::vector<float> expected(values.size());
    for (size_t v = 0; v < values.size(); ++v)
    {
      expected[v] = static_cast<float>(transfer->Evaluate(static_cast<double>(values[v])));
    }
    auto owner = itk::ImportImageContainer<itk::SizeValueType, int16_t>::New();
    auto inPlace = itk::DRRAttenuationVolume::New();
    inPlace->Build(values.data(), everySize, *transfer, nullptr, owner.GetPointer());
    auto copied = itk::DRRAttenuationVolume::New();
    copied->Build(values.data(), everySize, *transfer, nullptr);
    auto fromFloat = itk::DRRAttenuationVolume::New();
    fromFloat->Build(asFloat.data(), everySize, *transfer, nullptr);
    // The copy costs its 2 bytes per voxel; in place, nothing per voxel (the key table aside).
    EXPECT_DOUBLE_EQ(copied->GetBytesPerVoxel() - inPlace->GetBytesPerVoxel(), 2.0) << named.first;
    const std::vector<std::pair<std::string, itk::DRRAttenuationVolume *>> volumes{
      { "in place", inPlace.GetPointer() }, { "copied", copied.GetPointer() }, { "float", fromFloat.GetPointer() }
    };
    for (const auto & volume : volumes)
    {
      const std::string context = named.first + ", " + volume.first;
      ASSERT_TRUE(volume.second->HasLevels()) << context;
      EXPECT_EQ(FirstDifference(ReadByRows(*volume.second), expected.data(), &values), "") << context << " by rows";
      EXPECT_EQ(FirstDifference(ReadByBoxes(*volume.second, 4), expected.data(), &values), "")
        << context << " by boxes";
      EXPECT_EQ(FirstDifference(expected, volume.second->GetMuBuffer(), &values), "") << context << " materialized";
    }
  }
}

// A 16-bit CT read in place costs nothing per voxel until a consumer asks for mu or level lists, and they are then
// built from the keys.
TEST(DRRAttenuationVolume, InPlaceKeysAddNoBytePerVoxelUntilMuOrLevelListsAreAskedFor)
{
  const itk::DRRAttenuationVolume::SizeType size{ { 256, 128, 64 } };
  const std::vector<int16_t>                values = RandomHU(size, -1100, 1500, 3);
  const auto                                volume = BuildInPlace(values, size);
  EXPECT_LT(volume->GetBytesPerVoxel(), 0.2); // the key table alone
  const uint32_t * voxels = volume->GetLevelVoxels();
  ASSERT_NE(voxels, nullptr);
  const float * mu = volume->GetMuBuffer();
  uint64_t      wrong = 0;
  for (size_t l = 0; l < volume->GetNumberOfLevels(); ++l)
  {
    for (uint64_t e = volume->GetLevelStart(l); e < volume->GetLevelStart(l + 1); ++e)
    {
      wrong += mu[voxels[e]] != volume->GetLevelMu(l) ? 1 : 0;
      wrong += e > volume->GetLevelStart(l) && voxels[e] <= voxels[e - 1] ? 1 : 0;
    }
  }
  EXPECT_EQ(wrong, 0u);
  uint64_t nonAir = 0;
  for (uint64_t v = 0; v < volume->GetNumberOfVoxels(); ++v)
  {
    nonAir += mu[v] > 0.0f ? 1 : 0;
  }
  EXPECT_EQ(volume->GetLevelStart(volume->GetNumberOfLevels()), nonAir);
  EXPECT_GT(volume->GetBytesPerVoxel(), 4.0); // mu and the lists, now asked for
}

// The residual volume computes |mu - mu_c| from the volume's rows and the block means: the same bits as the
// definition, with the padding past the volume's end (air less the block mean), by rows, by boxes and materialized,
// and its signed rows and sum agree.
TEST(DRRAttenuationVolume, ResidualRowsEqualTheDefinitionIncludingThePadding)
{
  const itk::DRRAttenuationVolume::SizeType size{ { 37, 22, 13 } }; // no axis a multiple of 2, 4 or 8
  const std::vector<int16_t>                values = RandomHU(size, -1000, 2000, 11);
  const auto                                volume = BuildInPlace(values, size);
  const auto transfer = itk::DRRTransferFunction::New(); // BuildInPlace()'s, for the definition
  for (const unsigned int F : { 2u, 3u, 4u, 8u })
  {
    const std::string context = "F " + std::to_string(F);
    auto              split = itk::DRRControlVariate::New();
    split->Build(*volume, F, nullptr);
    const itk::DRRAttenuationVolume & coarse = split->GetCoarseVolume();
    const itk::DRRAttenuationVolume & residual = split->GetResidualVolume();
    ASSERT_TRUE(residual.IsResidual()) << context;
    const auto & padded = residual.GetSize();
    const auto & coarseSize = coarse.GetSize();
    for (unsigned int a = 0; a < 3; ++a)
    {
      ASSERT_EQ(padded[a], coarseSize[a] * F) << context;
    }
    // The definition, voxel by voxel, and the block means from the definition.
    std::vector<float>  expected(residual.GetNumberOfVoxels());
    std::vector<double> signedResidual(expected.size());
    double              sum = 0.0;
    const float *       coarseMu = coarse.GetMuBuffer();
    for (uint64_t k = 0; k < padded[2]; ++k)
    {
      for (uint64_t j = 0; j < padded[1]; ++j)
      {
        for (uint64_t i = 0; i < padded[0]; ++i)
        {
          const bool   inside = i < size[0] && j < size[1] && k < size[2];
          const double fine =
            inside ? static_cast<float>(transfer->Evaluate(values[i + size[0] * (j + size[1] * k)])) : 0.0;
          const double   c = coarseMu[i / F + coarseSize[0] * (j / F + coarseSize[1] * (k / F))];
          const uint64_t v = i + padded[0] * (j + padded[1] * k);
          signedResidual[v] = fine - c;
          expected[v] = static_cast<float>(std::abs(fine - c));
          sum += expected[v];
        }
      }
    }
    EXPECT_EQ(FirstDifference(ReadByRows(residual), expected.data()), "") << context << " by rows";
    EXPECT_EQ(FirstDifference(ReadByBoxes(residual, 4), expected.data()), "") << context << " by boxes";
    EXPECT_EQ(FirstDifference(expected, residual.GetMuBuffer()), "") << context << " materialized";
    std::vector<double> row(padded[0]);
    uint64_t            signs = 0;
    for (uint64_t k = 0; k < padded[2]; ++k)
    {
      for (uint64_t j = 0; j < padded[1]; ++j)
      {
        residual.FillResidualRow(0, j, k, padded[0], row.data());
        for (uint64_t i = 0; i < padded[0]; ++i)
        {
          const uint64_t v = i + padded[0] * (j + padded[1] * k);
          signs += row[i] != signedResidual[v] ? 1 : 0;
          const bool negative = residual.IsNegativeResidual(i, j, k);
          signs += negative != (signedResidual[v] < 0.0) ? 1 : 0;
        }
      }
    }
    EXPECT_EQ(signs, 0u) << context << ": signed rows or sign bits differ from the definition";
    EXPECT_NEAR(residual.ComputeMuSum(), sum, 1e-9 * sum) << context;
  }
}

// The stratified sampler's brick sums (mass and occupancy of every 8^3 brick) against a direct sum over the brick's
// voxels, on a volume whose bricks are cut by its end on every axis, plain and as a control variate's residual. A
// pass that drops a brick's boundary layer, or counts one twice, changes the brick's sum.
// A mask (the labels a render leaves out) makes voxels air: mu 0, in no level; the levels left keep their order and
// list their kept voxels. A volume of keys stays one (the masked voxels set to an air key: 2 bytes per voxel, no mu
// per voxel); a volume with no air key in its range takes the compaction of its level lists. Both against a direct
// computation from the unmasked volume.
TEST(DRRAttenuationVolume, AMaskMakesVoxelsAirAndKeepsTheKeysWhereTheRangeHasAnAirKey)
{
  const itk::DRRAttenuationVolume::SizeType size{ { 37, 21, 13 } };
  for (const int lowest : { -1300, 0 }) // air keys in range; every key of the range tissue (each present)
  {
    const std::vector<int16_t> values = RandomHU(size, lowest, lowest < 0 ? 1000 : 300, 11);
    const auto                 whole = BuildInPlace(values, size);
    const auto                 masked = BuildInPlace(values, size);
    std::vector<uint8_t>       keep(values.size());
    std::mt19937               random(12);
    for (auto & k : keep)
    {
      k = static_cast<uint8_t>(random() % 3 != 0); // a third masked
    }
    masked->ApplyVoxelMask(keep.data(), nullptr);
    const std::string context = "HU from " + std::to_string(lowest);
    if (lowest < -1000)
    {
      EXPECT_NEAR(masked->GetBytesPerVoxel(), 2.0, 65536.0 * 4.0 / static_cast<double>(values.size()) + 1e-9)
        << context << ": the keys copied, nothing else per voxel";
    }
    const std::vector<float> wholeMu = ReadByRows(*whole);
    const std::vector<float> maskedMu = ReadByRows(*masked);
    for (size_t v = 0; v < values.size(); ++v)
    {
      ASSERT_EQ(maskedMu[v], keep[v] ? wholeMu[v] : 0.0f) << context << ", voxel " << v;
    }
    // The levels: the unmasked volume's, each listing its kept voxels, the empty ones gone.
    std::vector<float>    levelMu;
    std::vector<uint64_t> levelStart{ 0 };
    std::vector<uint32_t> listed;
    for (size_t l = 0; l < whole->GetNumberOfLevels(); ++l)
    {
      for (uint64_t e = whole->GetLevelStart(l); e < whole->GetLevelStart(l + 1); ++e)
      {
        const uint32_t v = whole->GetLevelVoxels()[e];
        if (keep[v])
        {
          listed.push_back(v);
        }
      }
      if (listed.size() > levelStart.back())
      {
        levelMu.push_back(whole->GetLevelMu(l));
        levelStart.push_back(listed.size());
      }
    }
    ASSERT_EQ(masked->GetNumberOfLevels(), levelMu.size()) << context;
    for (size_t l = 0; l < levelMu.size(); ++l)
    {
      EXPECT_EQ(masked->GetLevelMu(l), levelMu[l]) << context << ", level " << l;
      EXPECT_EQ(masked->GetLevelStart(l + 1), levelStart[l + 1]) << context << ", level " << l;
    }
    const uint32_t * maskedListed = masked->GetLevelVoxels();
    EXPECT_TRUE(std::equal(listed.begin(), listed.end(), maskedListed)) << context;
    EXPECT_EQ(
      masked->ComputeTotalMass(),
      masked->GetVoxelVolume() *
        [&]() {
          double sum = 0.0;
          for (size_t l = 0; l < levelMu.size(); ++l)
          {
            sum += static_cast<double>(levelStart[l + 1] - levelStart[l]) * static_cast<double>(levelMu[l]);
          }
          return sum;
        }())
      << context;
  }
}

// A slab of whole brick planes must be one stretch of the curve (a streamed render draws the unstreamed points: the
// shared design, section 11): bricks by plane in z, each plane in 2-D Morton order of x and y (bit i of x at bit 2i).
TEST(DRRStratifiedSampler, TheCurveTakesBrickPlanesInZEachIn2DMortonOrder)
{
  const itk::DRRAttenuationVolume::SizeType size{ { 70, 37, 41 } }; // 9 x 5 x 6 bricks, partial at every far side
  const std::vector<int16_t>                values = RandomHU(size, -1300, 1800, 7);
  const auto                                volume = BuildInPlace(values, size);
  auto                                      sampler = itk::DRRStratifiedSampler::New();
  sampler->Initialize(*volume);
  const auto morton2D = [](uint64_t x, uint64_t y) {
    uint64_t code = 0;
    for (unsigned int bit = 0; bit < 16; ++bit)
    {
      code |= ((x >> bit) & 1u) << (2 * bit) | ((y >> bit) & 1u) << (2 * bit + 1);
    }
    return code;
  };
  ASSERT_EQ(sampler->GetNumberOfBricks(), 9u * 5u * 6u); // no brick of random HU is all air
  for (size_t b = 1; b < sampler->GetNumberOfBricks(); ++b)
  {
    const auto before = sampler->GetBrickSummary(b - 1);
    const auto brick = sampler->GetBrickSummary(b);
    const bool inOrder = before.Origin[2] < brick.Origin[2] ||
                         (before.Origin[2] == brick.Origin[2] && morton2D(before.Origin[0] / 8, before.Origin[1] / 8) <
                                                                   morton2D(brick.Origin[0] / 8, brick.Origin[1] / 8));
    EXPECT_TRUE(inOrder) << "brick " << b << " at voxel " << brick.Origin[0] << ", " << brick.Origin[1] << ", "
                         << brick.Origin[2] << " follows the brick at " << before.Origin[0] << ", " << before.Origin[1]
                         << ", " << before.Origin[2];
  }
}

// Empty bricks between non-empty ones, on every axis and in partial bricks at the far sides: the sampler keeps exactly
// the non-empty bricks, still in curve order (planes in z, 2-D Morton order inside a plane), each with its own count
// and sum. The bricks are placed on the curve as they are built and the empty ones dropped afterwards: a kept brick
// moved to the wrong place, or an empty one kept, fails here.
TEST(DRRStratifiedSampler, KeepsTheNonEmptyBricksAloneInCurveOrder)
{
  const itk::DRRAttenuationVolume::SizeType size{ { 43, 29, 35 } }; // 6 x 4 x 5 bricks, partial at every far side
  std::vector<int16_t>                      values(size[0] * size[1] * size[2], -1300);
  const auto occupiedBrick = [](uint64_t bx, uint64_t by, uint64_t bz) { return (bx + 2 * by + 3 * bz) % 4 == 1; };
  std::vector<uint64_t> expectedVoxels(6 * 4 * 5, 0);
  for (uint64_t k = 0; k < size[2]; ++k)
  {
    for (uint64_t j = 0; j < size[1]; ++j)
    {
      for (uint64_t i = 0; i < size[0]; ++i)
      {
        // A few voxels of tissue (a diagonal of the brick) in the occupied bricks, air elsewhere.
        if (occupiedBrick(i / 8, j / 8, k / 8) && i % 8 == j % 8 && (k % 8) % 3 == 0)
        {
          values[i + size[0] * (j + size[1] * k)] = static_cast<int16_t>(100 + (i * 7 + j * 3 + k) % 900);
          ++expectedVoxels[i / 8 + 6 * (j / 8 + 4 * (k / 8))];
        }
      }
    }
  }
  const auto volume = BuildInPlace(values, size);
  auto       sampler = itk::DRRStratifiedSampler::New();
  sampler->Initialize(*volume);
  const auto curve = [](const itk::DRRStratifiedSampler::BrickSummary & brick) {
    uint64_t code = 0;
    for (unsigned int bit = 0; bit < 16; ++bit)
    {
      code |= ((brick.Origin[0] / 8 >> bit) & 1u) << (2 * bit) | ((brick.Origin[1] / 8 >> bit) & 1u) << (2 * bit + 1);
    }
    return brick.Origin[2] / 8 << 32 | code;
  };
  uint64_t expectedBricks = 0;
  uint64_t expectedTotal = 0;
  for (const uint64_t count : expectedVoxels)
  {
    expectedBricks += count > 0 ? 1 : 0;
    expectedTotal += count;
  }
  ASSERT_GT(expectedBricks, 10u);
  ASSERT_LT(expectedBricks, expectedVoxels.size() / 2);
  ASSERT_EQ(sampler->GetNumberOfBricks(), expectedBricks);
  uint64_t total = 0;
  for (size_t b = 0; b < sampler->GetNumberOfBricks(); ++b)
  {
    const auto     brick = sampler->GetBrickSummary(b);
    const uint64_t index = brick.Origin[0] / 8 + 6 * (brick.Origin[1] / 8 + 4 * (brick.Origin[2] / 8));
    EXPECT_EQ(brick.NonAirVoxels, expectedVoxels[index])
      << "brick " << b << " at voxel " << brick.Origin[0] << ", " << brick.Origin[1] << ", " << brick.Origin[2];
    EXPECT_GT(brick.MuSum, 0.0) << "brick " << b;
    if (b > 0)
    {
      EXPECT_LT(curve(sampler->GetBrickSummary(b - 1)), curve(brick)) << "brick " << b << " out of curve order";
    }
    total += brick.NonAirVoxels;
  }
  EXPECT_EQ(total, expectedTotal);
  const auto plan = sampler->MakeViewPlan(*volume, nullptr, 0.0, 0.0);
  EXPECT_EQ(itk::DRRStratifiedSampler::GetNumberOfVoxelsInPlan(*plan), expectedTotal);
}

TEST(DRRStratifiedSampler, BrickSumsEqualADirectSumOverEveryBrick)
{
  const itk::DRRAttenuationVolume::SizeType size{ { 45, 30, 19 } };
  const std::vector<int16_t>                values = RandomHU(size, -1300, 1800, 5); // a third of the voxels air
  const auto                                volume = BuildInPlace(values, size);
  auto                                      split = itk::DRRControlVariate::New();
  split->Build(*volume, 4, nullptr);
  const std::vector<const itk::DRRAttenuationVolume *> sampledVolumes{ volume.GetPointer(),
                                                                       &split->GetResidualVolume() };
  for (const itk::DRRAttenuationVolume * sampled : sampledVolumes)
  {
    const std::string context = sampled->IsResidual() ? "residual" : "volume";
    auto              sampler = itk::DRRStratifiedSampler::New();
    sampler->Initialize(*sampled);
    const std::vector<float> mu = ReadByRows(*sampled);
    const auto &             grid = sampled->GetSize();
    // Direct sums per brick, in double.
    const uint64_t        bricksX = (grid[0] + 7) / 8, bricksY = (grid[1] + 7) / 8, bricksZ = (grid[2] + 7) / 8;
    std::vector<double>   direct(bricksX * bricksY * bricksZ, 0.0);
    std::vector<uint64_t> occupied(direct.size(), 0);
    double                total = 0.0;
    for (uint64_t k = 0; k < grid[2]; ++k)
    {
      for (uint64_t j = 0; j < grid[1]; ++j)
      {
        for (uint64_t i = 0; i < grid[0]; ++i)
        {
          const float    m = mu[i + grid[0] * (j + grid[1] * k)];
          const uint64_t brick = i / 8 + bricksX * (j / 8 + bricksY * (k / 8));
          direct[brick] += m;
          occupied[brick] += m > 0.0f ? 1 : 0;
          total += m;
        }
      }
    }
    uint64_t nonEmpty = 0;
    for (const uint64_t count : occupied)
    {
      nonEmpty += count > 0 ? 1 : 0;
    }
    ASSERT_EQ(sampler->GetNumberOfBricks(), nonEmpty) << context;
    for (size_t b = 0; b < sampler->GetNumberOfBricks(); ++b)
    {
      const itk::DRRStratifiedSampler::BrickSummary brick = sampler->GetBrickSummary(b);
      const uint64_t index = brick.Origin[0] / 8 + bricksX * (brick.Origin[1] / 8 + bricksY * (brick.Origin[2] / 8));
      EXPECT_NEAR(brick.MuSum, direct[index], 1e-12 * direct[index])
        << context << ", brick at voxel " << brick.Origin[0] << ", " << brick.Origin[1] << ", " << brick.Origin[2];
      EXPECT_EQ(brick.NonAirVoxels, occupied[index]) << context << ", brick " << b;
    }
    EXPECT_NEAR(sampler->GetTotalMass(), total * sampled->GetVoxelVolume(), 1e-12 * total) << context;
  }
}

namespace
{
/** numberOfSamples points (a multiple of 4) drawn by a stratified sampler from the whole of the volume it was
 * initialized with: (i, j, k) of each, then its weight's bits, in one vector. */
std::vector<uint64_t>
DrawWholeVolume(const itk::DRRStratifiedSampler & sampler, const itk::DRRAttenuationVolume & volume, uint64_t count)
{
  const auto                            plan = sampler.MakeViewPlan(volume, nullptr, 0.0, 0.0);
  const uint64_t                        room = count + itk::DRRPointSampler::CoordinateSlack;
  std::vector<uint32_t>                 i(room), j(room), k(room), stratum(room), jx(room), jy(room), jz(room);
  std::vector<double>                   weight(room);
  std::vector<uint64_t>                 voxel(room);
  itk::DRRPointSampler::SampleRange     range;
  itk::DRRPointSampler::Cursor          cursor;
  itk::DRRPointSampler::CoordinateBatch batch{ i.data(),  j.data(),  k.data(),  weight.data(), stratum.data(),
                                               jx.data(), jy.data(), jz.data(), voxel.data() };
  itk::detail::DRRPhiloxRandom          random(7, 0, 0);
  range.Seed = 7;
  range.Count = count;
  range.StratumSize = count;
  range.NumberOfStrata = 4;
  sampler.GenerateCoordinates(*plan, random, range, cursor, batch);
  std::vector<uint64_t> drawn;
  for (uint64_t s = 0; s < count; ++s)
  {
    uint64_t bits;
    std::memcpy(&bits, &weight[s], sizeof(bits));
    drawn.insert(drawn.end(), { i[s], j[s], k[s], bits });
  }
  return drawn;
}
} // namespace

// The split and the sampler's tables made in one pass (InitializeWithControlVariate(), what the filter does) are those
// made one after the other, bit for bit: the coarse volume, every brick, the mass and the points drawn; for the
// factors of the one pass (2, 4, 8, 16), for one that falls back to two (3), on 1 and 3 threads, on a grid that no
// factor and no brick divides. Build() hands each of the residual's rows once, equal to the residual volume's row.
TEST(DRRControlVariate, OnePassGivesTheSplitAndTheTablesOfOneAfterTheOther)
{
  const itk::DRRAttenuationVolume::SizeType size{ { 45, 38, 21 } };
  const std::vector<int16_t>                values = RandomHU(size, -1300, 1800, 11); // a third of the voxels air
  const auto                                volume = BuildInPlace(values, size);
  for (const unsigned int threads : { 1u, 3u })
  {
    auto threader = itk::PlatformMultiThreader::New();
    threader->SetNumberOfWorkUnits(threads);
    threader->SetMaximumNumberOfThreads(threads);
    for (const unsigned int factor : { 2u, 3u, 4u, 8u, 16u })
    {
      const std::string context = "F " + std::to_string(factor) + ", " + std::to_string(threads) + " threads";
      auto              apart = itk::DRRControlVariate::New();
      apart->Build(*volume, factor, threader);
      auto tablesApart = itk::DRRStratifiedSampler::New();
      tablesApart->Initialize(apart->GetResidualVolume());
      auto together = itk::DRRControlVariate::New();
      auto tablesTogether = itk::DRRStratifiedSampler::New();
      tablesTogether->InitializeWithControlVariate(*together, *volume, factor, threader);

      const auto & coarse = together->GetCoarseVolume();
      ASSERT_EQ(coarse.GetSize(), apart->GetCoarseVolume().GetSize()) << context;
      EXPECT_EQ(std::memcmp(coarse.GetMuBuffer(),
                            apart->GetCoarseVolume().GetMuBuffer(),
                            sizeof(float) * coarse.GetNumberOfVoxels()),
                0)
        << context;
      ASSERT_EQ(together->GetResidualVolume().GetSize(), apart->GetResidualVolume().GetSize()) << context;
      EXPECT_EQ(together->GetResidualVolume().GetSize(), itk::DRRControlVariate::ComputeResidualSize(size, factor))
        << context;
      EXPECT_EQ(together->GetTotalMass(), apart->GetTotalMass()) << context;
      ASSERT_EQ(tablesTogether->GetNumberOfBricks(), tablesApart->GetNumberOfBricks()) << context;
      for (size_t b = 0; b < tablesApart->GetNumberOfBricks(); ++b)
      {
        const auto one = tablesTogether->GetBrickSummary(b);
        const auto two = tablesApart->GetBrickSummary(b);
        EXPECT_TRUE(one.Origin[0] == two.Origin[0] && one.Origin[1] == two.Origin[1] && one.Origin[2] == two.Origin[2])
          << context << ", brick " << b;
        EXPECT_EQ(one.MuSum, two.MuSum) << context << ", brick " << b;
        EXPECT_EQ(one.NonAirVoxels, two.NonAirVoxels) << context << ", brick " << b;
      }
      EXPECT_EQ(tablesTogether->GetTotalMass(), tablesApart->GetTotalMass()) << context;
      EXPECT_EQ(DrawWholeVolume(*tablesTogether, together->GetResidualVolume(), 4096),
                DrawWholeVolume(*tablesApart, apart->GetResidualVolume(), 4096))
        << context;

      // The rows handed out: each once, in sets of whole bricks, equal to the residual volume's.
      const auto &          residual = apart->GetResidualVolume();
      const auto &          grid = residual.GetSize();
      std::vector<uint32_t> handed(grid[1] * grid[2], 0);
      std::vector<float>    expected(grid[0]);
      std::mutex            mutex;
      auto                  visited = itk::DRRControlVariate::New();
      visited->Build(*volume, factor, threader, [&](const itk::DRRControlVariate::ResidualRows & rows) {
        std::lock_guard<std::mutex> lock(mutex);
        EXPECT_EQ(rows.Width, grid[0]) << context;
        EXPECT_TRUE(rows.FirstRow % 8 == 0 && rows.FirstPlane % 8 == 0) << context;
        EXPECT_TRUE((rows.NumberOfRows % 8 == 0 || rows.FirstRow + rows.NumberOfRows == grid[1]) &&
                    (rows.NumberOfPlanes % 8 == 0 || rows.FirstPlane + rows.NumberOfPlanes == grid[2]))
          << context;
        for (uint64_t z = rows.FirstPlane; z < rows.FirstPlane + rows.NumberOfPlanes && z < grid[2]; ++z)
        {
          for (uint64_t y = rows.FirstRow; y < rows.FirstRow + rows.NumberOfRows && y < grid[1]; ++y)
          {
            ++handed[y + grid[1] * z];
            residual.FillMuRow(0, y, z, grid[0], expected.data());
            const float * row = rows.Mu + rows.Width * (y - rows.FirstRow + rows.NumberOfRows * (z - rows.FirstPlane));
            EXPECT_EQ(std::memcmp(row, expected.data(), sizeof(float) * grid[0]), 0)
              << context << ", row y " << y << ", z " << z;
          }
        }
      });
      EXPECT_EQ(std::count(handed.begin(), handed.end(), 1u), static_cast<std::ptrdiff_t>(handed.size())) << context;
    }
  }
  // A factor that is none is refused before any table is laid out (F 10^5 would pad the grid to 10^15 voxels).
  for (const unsigned int factor : { 0u, 1u, itk::DRRControlVariate::MaximumFactor + 1, 100000u })
  {
    auto sampler = itk::DRRStratifiedSampler::New();
    auto split = itk::DRRControlVariate::New();
    EXPECT_NE(PointBasedDRRTest::ExceptionMessage(
                [&] { sampler->InitializeWithControlVariate(*split, *volume, factor, nullptr); }, "factor")
                .find("coarsening factor must be 2 to"),
              std::string::npos)
      << "F " << factor;
  }
}
