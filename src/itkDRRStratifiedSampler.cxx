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
#include "itkDRRStratifiedSampler.h"

#include <algorithm>
#include <array>
#include <limits>

namespace itk
{
namespace
{
constexpr unsigned int brickBits = 3; // 8 x 8 x 8 voxels per brick

/** Interleaves the bits of x, y, z (x lowest): the Morton code. */
uint64_t
MortonCode(uint64_t x, uint64_t y, uint64_t z)
{
  uint64_t code = 0;
  for (unsigned int bit = 0; bit < 21; ++bit)
  {
    code |= ((x >> bit) & 1u) << (3 * bit) | ((y >> bit) & 1u) << (3 * bit + 1) | ((z >> bit) & 1u) << (3 * bit + 2);
  }
  return code;
}

/** Offsets of the voxels of a brick, or of the bricks of the volume, in Morton order. */
std::vector<std::array<uint64_t, 3>>
MortonOrder(uint64_t nx, uint64_t ny, uint64_t nz)
{
  std::vector<std::pair<uint64_t, std::array<uint64_t, 3>>> coded;
  coded.reserve(nx * ny * nz);
  for (uint64_t z = 0; z < nz; ++z)
  {
    for (uint64_t y = 0; y < ny; ++y)
    {
      for (uint64_t x = 0; x < nx; ++x)
      {
        coded.push_back({ MortonCode(x, y, z), { { x, y, z } } });
      }
    }
  }
  std::sort(coded.begin(), coded.end(), [](const auto & a, const auto & b) { return a.first < b.first; });
  std::vector<std::array<uint64_t, 3>> order;
  order.reserve(coded.size());
  for (const auto & c : coded)
  {
    order.push_back(c.second);
  }
  return order;
}
} // namespace

void
DRRStratifiedSampler::Initialize(const DRRAttenuationVolume & volume)
{
  const auto &   size = volume.GetSize();
  const float *  mu = volume.GetMuBuffer();
  const uint64_t brick = uint64_t{ 1 } << brickBits;
  if (volume.GetNumberOfVoxels() > std::numeric_limits<uint32_t>::max())
  {
    itkExceptionMacro("volumes of more than 2^32 - 1 voxels are not supported (got " << volume.GetNumberOfVoxels()
                                                                                     << ")");
  }
  const auto bricks =
    MortonOrder((size[0] + brick - 1) / brick, (size[1] + brick - 1) / brick, (size[2] + brick - 1) / brick);
  const auto inside = MortonOrder(brick, brick, brick);
  m_Order.clear();
  m_Cumulative.clear();
  double running = 0.0;
  for (const auto & b : bricks)
  {
    for (const auto & o : inside)
    {
      const uint64_t x = b[0] * brick + o[0];
      const uint64_t y = b[1] * brick + o[1];
      const uint64_t z = b[2] * brick + o[2];
      if (x >= size[0] || y >= size[1] || z >= size[2])
      {
        continue;
      }
      const uint64_t v = x + size[0] * (y + size[1] * z);
      if (mu[v] > 0.0f)
      {
        running += mu[v];
        m_Order.push_back(static_cast<uint32_t>(v));
        m_Cumulative.push_back(running);
      }
    }
  }
  m_TotalMass = running * volume.GetVoxelVolume();
  m_MaximumWeight = 1.0;
  this->Modified();
}

void
DRRStratifiedSampler::GenerateBatch(DRRPhiloxRandom &,
                                    const SampleRange & range,
                                    uint64_t *          voxelIndex,
                                    double *            weight) const
{
  if (m_Order.empty())
  {
    return;
  }
  // One offset per stratum, from a stream of its own: the same for every chunk of the stratum on every thread.
  DRRPhiloxRandom                  offsetStream(range.Seed, range.Stratum, 2);
  const DRRPhiloxRandom::BlockType bits = offsetStream.Next();
  const double   offset = static_cast<double>((static_cast<uint64_t>(bits[1]) << 21) ^ (bits[0] >> 11)) * 0x1.0p-53;
  const double   step = m_Cumulative.back() / static_cast<double>(range.StratumSize);
  const uint64_t last = m_Order.size() - 1;
  const uint64_t firstIndex = range.First - range.StratumFirst;
  uint64_t       position = static_cast<uint64_t>(
    std::upper_bound(m_Cumulative.begin(), m_Cumulative.end(), (offset + static_cast<double>(firstIndex)) * step) -
    m_Cumulative.begin());
  for (uint64_t i = 0; i < range.Count; ++i)
  {
    const double target = (offset + static_cast<double>(firstIndex + i)) * step;
    if (position < last && m_Cumulative[position] <= target)
    {
      // Gallop: points are dense (a step or two) at large N, sparse (thousands of voxels apart) at small N.
      uint64_t low = position;
      uint64_t stride = 1;
      while (low + stride < last && m_Cumulative[low + stride] <= target)
      {
        low += stride;
        stride *= 2;
      }
      const auto begin = m_Cumulative.begin() + static_cast<std::ptrdiff_t>(low + 1);
      const auto end = m_Cumulative.begin() + static_cast<std::ptrdiff_t>(std::min(last, low + stride) + 1);
      position = static_cast<uint64_t>(std::upper_bound(begin, end, target) - m_Cumulative.begin());
    }
    position = std::min(position, last);
    voxelIndex[i] = m_Order[position];
    weight[i] = 1.0;
  }
}
void
DRRStratifiedSampler::GenerateJitter(const SampleRange & range, uint32_t * bits) const
{
  // R2: x_i = frac(shift + i alpha), alpha_k = 1 / phi^k with phi the plastic number (phi^3 = phi + 1). In 0.64 fixed
  // point the fractional part is the wrap-around of unsigned arithmetic. The shift is uniform and new per stratum.
  constexpr uint64_t               alpha[3] = { 0xC13FA9A902A6328Full, 0x91E10DA5C79E7B1Cull, 0x6E1EF25A386184E3ull };
  DRRPhiloxRandom                  shiftStream(range.Seed, range.Stratum, 4);
  const DRRPhiloxRandom::BlockType a = shiftStream.Next();
  const DRRPhiloxRandom::BlockType b = shiftStream.Next();
  const uint64_t                   shift[3] = { (uint64_t{ a[0] } << 32) | a[1],
                                                (uint64_t{ a[2] } << 32) | a[3],
                                                (uint64_t{ b[0] } << 32) | b[1] };
  const uint64_t                   first = range.First - range.StratumFirst;
  for (uint64_t i = 0; i < range.Count; ++i)
  {
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      bits[3 * i + axis] = static_cast<uint32_t>((shift[axis] + (first + i) * alpha[axis]) >> 32);
    }
  }
}
} // namespace itk
