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
#include "itkDRRPassCombination.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <stdexcept>

namespace itk
{
namespace
{
/** sum += scale * value, element by element (square: scale * value^2). */
void
AddScaled(std::vector<double> & sum, const std::vector<double> & values, double scale, bool square)
{
  sum.resize(values.size(), 0.0);
  for (size_t i = 0; i < values.size(); ++i)
  {
    sum[i] += scale * (square ? values[i] * values[i] : values[i]);
  }
}
} // namespace

void
DRRPassCombination::Clear()
{
  *this = DRRPassCombination();
}

void
DRRPassCombination::Add(const DRRPointRenderer::Result & pass, uint64_t requestedSamples)
{
  const uint64_t points = pass.NumberOfSamples > 0 ? pass.NumberOfSamples : requestedSamples;
  if (points == 0)
  {
    throw std::invalid_argument("a render pass of no point");
  }
  if (m_NumberOfPasses > 0 && (pass.LineIntegral.size() != m_FirstPass.LineIntegral.size() ||
                               pass.ChannelLineIntegral.size() != m_FirstPass.ChannelLineIntegral.size()))
  {
    throw std::invalid_argument("a render pass of another image size than the first");
  }
  if (m_NumberOfPasses == 0)
  {
    m_FirstPass = { pass.LineIntegral, pass.StandardError, pass.ChannelLineIntegral, pass.ChannelCovariance };
  }
  const double n = static_cast<double>(points);
  AddScaled(m_WeightedSum.LineIntegral, pass.LineIntegral, n, false);
  AddScaled(m_WeightedSum.StandardError, pass.StandardError, n * n, true);
  AddScaled(m_WeightedSum.ChannelLineIntegral, pass.ChannelLineIntegral, n, false);
  AddScaled(m_WeightedSum.ChannelCovariance, pass.ChannelCovariance, n * n, false);
  ++m_NumberOfPasses;
  m_NumberOfSamples += points;
  m_PointsOnDetector += pass.PointsOnDetector;
}

DRRPassCombination::Estimate
DRRPassCombination::Combine() const
{
  if (m_NumberOfPasses <= 1)
  {
    return m_FirstPass;
  }
  const double total = static_cast<double>(m_NumberOfSamples);
  Estimate     estimate = m_WeightedSum;
  for (double & value : estimate.LineIntegral)
  {
    value /= total;
  }
  for (double & variance : estimate.StandardError)
  {
    variance = std::sqrt(variance) / total;
  }
  for (double & value : estimate.ChannelLineIntegral)
  {
    value /= total;
  }
  for (double & covariance : estimate.ChannelCovariance)
  {
    covariance /= total * total;
  }
  return estimate;
}

double
DRRPassCombination::ComputeRelativeError(const Estimate & estimate)
{
  double sumOfSquares = 0.0;
  for (const double error : estimate.StandardError)
  {
    sumOfSquares += error * error;
  }
  if (!(sumOfSquares > 0.0))
  {
    return 0.0;
  }
  const auto   range = std::minmax_element(estimate.LineIntegral.begin(), estimate.LineIntegral.end());
  const double width = *range.second - *range.first;
  const double rms = std::sqrt(sumOfSquares / static_cast<double>(estimate.StandardError.size()));
  return width > 0.0 ? rms / width : std::numeric_limits<double>::infinity();
}
} // namespace itk
