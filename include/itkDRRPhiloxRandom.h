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
#ifndef itkDRRPhiloxRandom_h
#define itkDRRPhiloxRandom_h

#include "itkDRRCompilerSupport.h"

#include <array>
#include <cstdint>

namespace itk
{
namespace detail
{
/** \class DRRPhiloxRandom
 * \brief Counter-based random numbers (Philox4x32-10, Salmon et al., SC 2011) for reproducible parallel sampling.
 *
 * A stream is keyed by the user's seed and addressed by (chunk, stream id, position): the numbers of a chunk do not
 * depend on which thread draws them or in what order chunks run, which is what makes a seeded DRR the same bit for
 * bit on any number of threads.
 *
 * \sa DRRPointRenderer
 * \ingroup PointBasedDRR
 */
class DRRPhiloxRandom
{
public:
  /** 128 random bits: four 32-bit words. */
  using BlockType = std::array<uint32_t, 4>;

  /** The stream of a seed, a chunk (of samples) and a stream id (what the numbers are for), at its first position. */
  DRRPhiloxRandom(uint64_t seed, uint64_t chunk, uint32_t streamId)
    : m_Key{ { static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32) } }
    , m_Counter{ { 0u, streamId, static_cast<uint32_t>(chunk), static_cast<uint32_t>(chunk >> 32) } }
  {}

  /** The next 128 random bits; advances the position. */
  BlockType
  Next()
  {
    BlockType block = Philox(m_Counter, m_Key);
    ++m_Counter[0];
    return block;
  }

  /** Uniform in [0, 1) with 24 random bits (exactly representable in float and double). */
  static double
  ToUnitInterval(uint32_t bits)
  {
    return static_cast<double>(static_cast<int32_t>(bits >> 8)) * (1.0 / 16777216.0); // signed: converts in SIMD
  }

  /** Uniform integer in [0, n) from 64 random bits (multiply-shift; non-uniformity below n / 2^64). */
  static uint64_t
  ToRange(uint32_t low, uint32_t high, uint64_t n)
  {
    const uint64_t bits = (static_cast<uint64_t>(high) << 32) | low;
    return detail::DRRMultiplyHigh64(bits, n);
  }

  /** Uniform integer in [0, n) from 32 random bits, n < 2^32 (non-uniformity below n / 2^32). */
  static uint32_t
  ToRange32(uint32_t bits, uint32_t n)
  {
    return static_cast<uint32_t>((static_cast<uint64_t>(bits) * n) >> 32);
  }

  /** The Philox4x32-10 block function: 128 random bits for a counter and a 64-bit key (10 rounds). */
  static BlockType
  Philox(BlockType counter, std::array<uint32_t, 2> key)
  {
    constexpr uint32_t multiplier0 = 0xD2511F53u;
    constexpr uint32_t multiplier1 = 0xCD9E8D57u;
    constexpr uint32_t weyl0 = 0x9E3779B9u;
    constexpr uint32_t weyl1 = 0xBB67AE85u;
    for (unsigned int round = 0; round < 10; ++round)
    {
      const uint64_t product0 = static_cast<uint64_t>(multiplier0) * counter[0];
      const uint64_t product1 = static_cast<uint64_t>(multiplier1) * counter[2];
      const uint32_t hi0 = static_cast<uint32_t>(product0 >> 32);
      const uint32_t lo0 = static_cast<uint32_t>(product0);
      const uint32_t hi1 = static_cast<uint32_t>(product1 >> 32);
      const uint32_t lo1 = static_cast<uint32_t>(product1);
      counter = { { hi1 ^ counter[1] ^ key[0], lo1, hi0 ^ counter[3] ^ key[1], lo0 } };
      key[0] += weyl0;
      key[1] += weyl1;
    }
    return counter;
  }

private:
  std::array<uint32_t, 2> m_Key;
  BlockType               m_Counter;
};
} // namespace detail
} // namespace itk

#endif
