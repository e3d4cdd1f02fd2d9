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
#ifndef itkDRRCompilerSupport_h
#define itkDRRCompilerSupport_h

#include <cstdint>

/** \file itkDRRCompilerSupport.h
 * \brief The compiler built-ins that installed headers use, each with a portable fallback: the engine's, not an API.
 *
 * GCC and Clang get the built-ins the module was written with (the same instructions, hence the same bits); other
 * compilers ITK supports (MSVC) get portable code that computes the same values, or, for the hints (restrict,
 * prefetch), nothing: a hint changes speed, never a result. Only what a header of include/ needs is here: the
 * attenuation volume's reader prefetches (itkDRRAttenuationVolume.hxx), the projection's batch loop restricts its
 * pointers (itkDRRPointProjection.h), the random numbers' range reduction multiplies to 128 bits
 * (itkDRRPhiloxRandom.h). The built-ins only the compiled engine uses are in src/ (itkDRRCompilerBuiltins.h, not
 * installed).
 * \ingroup PointBasedDRR
 */

/** \def PointBasedDRR_RESTRICT
 * Pointer qualifier: the pointee is reached through no other pointer in its scope (lets loops vectorize). */
#if defined(__GNUC__) || defined(__clang__)
#define PointBasedDRR_RESTRICT __restrict__
#elif defined(_MSC_VER)
#define PointBasedDRR_RESTRICT __restrict
#else
#define PointBasedDRR_RESTRICT
#endif

/** \def PointBasedDRR_PREFETCH
 * Hint to fetch the cache line of address (rw: 0 read, 1 write; locality 0 to 3); a no-op where not supported. */
#if defined(__GNUC__) || defined(__clang__)
#define PointBasedDRR_PREFETCH(address, rw, locality) __builtin_prefetch((address), (rw), (locality))
#else
#define PointBasedDRR_PREFETCH(address, rw, locality) static_cast<void>(address)
#endif

#if defined(_MSC_VER) && !defined(__clang__)
#include <intrin.h>
#endif

namespace itk
{
namespace detail
{
/** The high 64 bits of the 128-bit product a b. */
inline uint64_t
DRRMultiplyHigh64(uint64_t a, uint64_t b)
{
#if defined(__SIZEOF_INT128__)
  return static_cast<uint64_t>((static_cast<unsigned __int128>(a) * b) >> 64);
#else
  // Schoolbook on 32-bit halves: exact.
  const uint64_t aLow = a & 0xFFFFFFFFu, aHigh = a >> 32;
  const uint64_t bLow = b & 0xFFFFFFFFu, bHigh = b >> 32;
  const uint64_t lowLow = aLow * bLow;
  const uint64_t highLow = aHigh * bLow;
  const uint64_t lowHigh = aLow * bHigh;
  const uint64_t highHigh = aHigh * bHigh;
  const uint64_t middle = (lowLow >> 32) + (highLow & 0xFFFFFFFFu) + (lowHigh & 0xFFFFFFFFu);
  return highHigh + (highLow >> 32) + (lowHigh >> 32) + (middle >> 32);
#endif
}
} // namespace detail
} // namespace itk

#endif
