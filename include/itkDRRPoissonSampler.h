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
#ifndef itkDRRPoissonSampler_h
#define itkDRRPoissonSampler_h

#include "itkDRRPhiloxRandom.h"

#include <cmath>
#include <cstdint>

namespace itk
{
namespace detail
{
/** \class DRRPoissonSampler
 * \brief Poisson random counts from a DRRPhiloxRandom stream: reproducible bit for bit, wherever they are drawn.
 *
 * Means below 10: inversion by sequential multiplication (Knuth, TAOCP vol. 2, 3.4.1); from 10: Hoermann's
 * transformed rejection with squeeze, PTRS (W. Hoermann, "The transformed rejection method for generating Poisson
 * random variables", Insurance: Mathematics and Economics 12, 1993, 39-45; the algorithm numpy's generator uses). The
 * uniforms carry 53 random bits, two per 128-bit block.
 *
 * \sa DRRQuantumNoiseImageFilter
 * \ingroup PointBasedDRR
 */
class DRRPoissonSampler
{
public:
  /** Largest mean Sample() takes (counts then fit an int64 and PTRS's double arithmetic by far). */
  static constexpr double MaximumMean = 1e15;

  /** A stream of uniforms on [0, 1) with 53 random bits each, drawn from stream. */
  explicit DRRPoissonSampler(DRRPhiloxRandom & stream) : m_Stream(stream) {}

  /** A Poisson count of the given mean (0 <= mean <= MaximumMean; a mean of 0 gives 0). */
  uint64_t
  Sample(double mean)
  {
    if (!(mean > 0.0))
    {
      return 0;
    }
    return mean < 10.0 ? this->SampleByInversion(mean) : this->SampleByTransformedRejection(mean);
  }

  /** The next uniform on [0, 1), 53 random bits. */
  double
  Uniform()
  {
    if (m_Next == 2)
    {
      m_Block = m_Stream.Next();
      m_Next = 0;
    }
    const uint64_t high = m_Block[2 * m_Next] >> 5;    // 27 bits
    const uint64_t low = m_Block[2 * m_Next + 1] >> 6; // 26 bits
    ++m_Next;
    return static_cast<double>((high << 26) | low) * (1.0 / 9007199254740992.0);
  }

private:
  uint64_t
  SampleByInversion(double mean)
  {
    const double limit = std::exp(-mean);
    double       product = this->Uniform();
    uint64_t     count = 0;
    while (product > limit)
    {
      product *= this->Uniform();
      ++count;
    }
    return count;
  }

  uint64_t
  SampleByTransformedRejection(double mean)
  {
    const double logMean = std::log(mean);
    const double b = 0.931 + 2.53 * std::sqrt(mean);
    const double a = -0.059 + 0.02483 * b;
    const double inverseAlpha = 1.1239 + 1.1328 / (b - 3.4);
    const double vr = 0.9277 - 3.6224 / (b - 2.0);
    while (true)
    {
      const double u = this->Uniform() - 0.5;
      const double v = this->Uniform();
      const double us = 0.5 - std::abs(u);
      const double k = std::floor((2.0 * a / us + b) * u + mean + 0.43);
      if (us >= 0.07 && v <= vr)
      {
        return static_cast<uint64_t>(k);
      }
      if (k < 0.0 || (us < 0.013 && v > us))
      {
        continue;
      }
      if (std::log(v) + std::log(inverseAlpha) - std::log(a / (us * us) + b) <=
          -mean + k * logMean - std::lgamma(k + 1.0))
      {
        return static_cast<uint64_t>(k);
      }
    }
  }

  DRRPhiloxRandom &          m_Stream;
  DRRPhiloxRandom::BlockType m_Block{};
  unsigned int               m_Next{ 2 };
};
} // namespace detail
} // namespace itk

#endif
