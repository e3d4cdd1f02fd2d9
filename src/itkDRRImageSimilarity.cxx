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
#include "itkDRRImageSimilarity.h"

#include "itkMacro.h"

#include <algorithm>
#include <cmath>

namespace itk
{
const std::vector<std::string> &
DRRImageSimilarity::GetMetricNames()
{
  static const std::vector<std::string> names{ "ncc", "gc" };
  return names;
}

bool
DRRImageSimilarity::IsMetricName(const std::string & name)
{
  const auto & names = GetMetricNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string
DRRImageSimilarity::JoinMetricNames(const std::string & separator)
{
  std::string joined;
  for (const std::string & name : GetMetricNames())
  {
    joined += (joined.empty() ? "" : separator) + name;
  }
  return joined;
}

namespace
{
/** The NCC of a and b over the pixels where mask is 1 (n pixels) and, unless derivative is null, dNCC/da_p (0 off the
 * mask): the one implementation of both metrics, in double whatever the pixel types. */
template <typename TA, typename TB>
double
Correlation(const TA * a, const TB * b, const uint8_t * mask, size_t n, double * derivative)
{
  if (derivative)
  {
    std::fill(derivative, derivative + n, 0.0);
  }
  double sa = 0.0, sb = 0.0, count = 0.0;
  for (size_t p = 0; p < n; ++p)
  {
    if (mask[p])
    {
      sa += a[p];
      sb += b[p];
      count += 1.0;
    }
  }
  if (count < 2.0)
  {
    return 0.0;
  }
  const double ma = sa / count, mb = sb / count;
  double       ab = 0.0, aa = 0.0, bb = 0.0;
  for (size_t p = 0; p < n; ++p)
  {
    if (mask[p])
    {
      const double da = a[p] - ma, db = b[p] - mb;
      ab += da * db;
      aa += da * da;
      bb += db * db;
    }
  }
  if (!(aa > 0.0 && bb > 0.0))
  {
    return 0.0;
  }
  const double norm = std::sqrt(aa * bb);
  const double r = ab / norm;
  if (derivative)
  {
    // d r / d a_p = b'_p / norm - r a'_p / aa; the means' own derivatives add sum b' = sum a' = 0.
    for (size_t p = 0; p < n; ++p)
    {
      if (mask[p])
      {
        derivative[p] = (b[p] - mb) / norm - r * (a[p] - ma) / aa;
      }
    }
  }
  return r;
}

/** The gradient correlation of a and b (columns wide) over the mask, and unless derivative is null dGC/da_p: the mean
 * of the NCCs of the central differences along the columns and along the rows, over the pixels whose two neighbours on
 * that axis are both in the mask. */
template <typename TA, typename TB>
double
GradientCorrelation(const TA * a, const TB * b, const std::vector<uint8_t> & mask, size_t columns, double * derivative)
{
  const size_t n = mask.size();
  const size_t rows = n / columns;
  if (derivative)
  {
    std::fill(derivative, derivative + n, 0.0);
  }
  std::vector<double>  da(n), db(n), dr(derivative ? n : 0);
  std::vector<uint8_t> inside(n);
  double               sum = 0.0;
  for (const bool alongColumns : { true, false })
  {
    const size_t step = alongColumns ? 1 : columns;
    std::fill(da.begin(), da.end(), 0.0);
    std::fill(db.begin(), db.end(), 0.0);
    std::fill(inside.begin(), inside.end(), uint8_t{ 0 });
    for (size_t r = alongColumns ? 0 : 1; r + (alongColumns ? 0 : 1) < rows; ++r)
    {
      for (size_t c = alongColumns ? 1 : 0; c + (alongColumns ? 1 : 0) < columns; ++c)
      {
        const size_t p = r * columns + c;
        inside[p] = mask[p - step] & mask[p + step];
        da[p] = static_cast<double>(a[p + step]) - static_cast<double>(a[p - step]);
        db[p] = static_cast<double>(b[p + step]) - static_cast<double>(b[p - step]);
      }
    }
    sum += Correlation(da.data(), db.data(), inside.data(), n, derivative ? dr.data() : nullptr);
    if (derivative)
    {
      // The adjoint of the difference: da_p = a_{p+step} - a_{p-step} sends dr_p to a_{p+step} and -dr_p to a_{p-step}.
      for (size_t p = 0; p < n; ++p)
      {
        if (dr[p] != 0.0)
        {
          derivative[p + step] += 0.5 * dr[p];
          derivative[p - step] -= 0.5 * dr[p];
        }
      }
    }
  }
  return 0.5 * sum;
}
} // namespace

auto
DRRImageSimilarity::FromName(const std::string & name) -> SimilarityEnum
{
  const auto & names = GetMetricNames();
  const auto   found = std::find(names.begin(), names.end(), name);
  if (found == names.end())
  {
    itkGenericExceptionMacro("unknown similarity metric '" << name << "' (" << JoinMetricNames(" or ") << ")");
  }
  return static_cast<SimilarityEnum>(found - names.begin());
}

const std::string &
DRRImageSimilarity::GetName(SimilarityEnum similarity)
{
  return GetMetricNames().at(static_cast<size_t>(similarity));
}

double
DRRImageSimilarity::MaskedNormalizedCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask)
{
  return Correlation(a, b, mask.data(), mask.size(), nullptr);
}

double
DRRImageSimilarity::MaskedGradientCorrelation(const float *                a,
                                              const float *                b,
                                              const std::vector<uint8_t> & mask,
                                              size_t                       columns)
{
  return GradientCorrelation(a, b, mask, columns, nullptr);
}

double
DRRImageSimilarity::Evaluate(const std::string &          metric,
                             const float *                a,
                             const float *                b,
                             const std::vector<uint8_t> & mask,
                             size_t                       columns)
{
  return FromName(metric) == SimilarityEnum::GradientCorrelation ? MaskedGradientCorrelation(a, b, mask, columns)
                                                                 : MaskedNormalizedCorrelation(a, b, mask);
}

double
DRRImageSimilarity::EvaluateWithDerivative(SimilarityEnum               similarity,
                                           const double *               a,
                                           const float *                b,
                                           const std::vector<uint8_t> & mask,
                                           size_t                       columns,
                                           double *                     derivative)
{
  return similarity == SimilarityEnum::GradientCorrelation ? GradientCorrelation(a, b, mask, columns, derivative)
                                                           : Correlation(a, b, mask.data(), mask.size(), derivative);
}
} // namespace itk
