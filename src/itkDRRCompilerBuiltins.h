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
#ifndef itkDRRCompilerBuiltins_h
#define itkDRRCompilerBuiltins_h

#include "itkDRRCompilerSupport.h"

#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/** \file itkDRRCompilerBuiltins.h
 * \brief The compiler built-ins only the compiled engine uses (src/, not installed), each with a portable fallback;
 * those installed headers use are in itkDRRCompilerSupport.h, which this header includes.
 *
 * As there: GCC and Clang get the built-ins the module was written with (the same instructions, hence the same bits);
 * other compilers get portable code that computes the same values, or, for the vector clones (a hint), nothing.
 * \ingroup PointBasedDRR
 */

/** \def PointBasedDRR_VECTOR_CLONES
 * Clones of a hot loop for wider vectors, picked once for the CPU at load time (GCC on x86-64 Linux), with its calls
 * inlined (flatten). Every clone gives the same bits: contraction into FMA is off (-ffp-contract=off) and every
 * operation used is correctly rounded. Not under ThreadSanitizer: the clones' resolver runs while the loader relocates
 * the program, before TSan's runtime has started, and GCC instruments it (a crash at load, before main). Empty
 * elsewhere. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) &&                           \
  !defined(__SANITIZE_THREAD__)
#define PointBasedDRR_VECTOR_CLONES __attribute__((target_clones("default", "avx2", "avx512f"), flatten))
#else
#define PointBasedDRR_VECTOR_CLONES
#endif

namespace itk
{
/** floor(a b / c) for c > 0 and a result below 2^64, without overflow of the product (128 bits). */
inline uint64_t
DRRMultiplyDivide64(uint64_t a, uint64_t b, uint64_t c)
{
#if defined(__SIZEOF_INT128__)
  return static_cast<uint64_t>((static_cast<unsigned __int128>(a) * b) / c);
#else
  // The 128-bit product (high, low), then long division one bit at a time: exact.
  uint64_t       high = detail::DRRMultiplyHigh64(a, b);
  uint64_t       low = a * b;
  uint64_t       quotient = 0;
  uint64_t       remainder = 0;
  const unsigned bits = 128;
  for (unsigned bit = 0; bit < bits; ++bit)
  {
    const bool carry = (remainder >> 63) != 0;
    remainder = (remainder << 1) | (high >> 63);
    high = (high << 1) | (low >> 63);
    low <<= 1;
    quotient <<= 1;
    if (carry || remainder >= c)
    {
      remainder -= c;
      quotient |= 1u;
    }
  }
  return quotient;
#endif
}

/** Index of the lowest set bit of bits (bits != 0). */
inline unsigned int
DRRCountTrailingZeros64(uint64_t bits)
{
#if defined(__GNUC__) || defined(__clang__)
  return static_cast<unsigned int>(__builtin_ctzll(bits));
#else
  unsigned int count = 0;
  while (!(bits & 1u))
  {
    bits >>= 1;
    ++count;
  }
  return count;
#endif
}

/** Number of set bits of bits. */
inline unsigned int
DRRPopCount64(uint64_t bits)
{
#if defined(__GNUC__) || defined(__clang__)
  return static_cast<unsigned int>(__builtin_popcountll(bits));
#else
  // SWAR count (no POPCNT instruction assumed).
  bits = bits - ((bits >> 1) & 0x5555555555555555ull);
  bits = (bits & 0x3333333333333333ull) + ((bits >> 2) & 0x3333333333333333ull);
  bits = (bits + (bits >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return static_cast<unsigned int>((bits * 0x0101010101010101ull) >> 56);
#endif
}

/** Which of the four floats value[0 .. 3] are positive (bit x: value[x] > 0; NaN is not): one compare of the four and
 * a move of their signs where SSE2 is there (every x86-64), four compares elsewhere. */
inline unsigned int
DRRPositiveMask4(const float * value)
{
#if defined(__SSE2__)
  return static_cast<unsigned int>(_mm_movemask_ps(_mm_cmpgt_ps(_mm_loadu_ps(value), _mm_setzero_ps())));
#else
  return unsigned{ value[0] > 0.0f } | unsigned{ value[1] > 0.0f } << 1 | unsigned{ value[2] > 0.0f } << 2 |
         unsigned{ value[3] > 0.0f } << 3;
#endif
}
} // namespace itk

#endif
