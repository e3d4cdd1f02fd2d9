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

double
DRRImageSimilarity::MaskedNormalizedCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask)
{
  double sa = 0.0, sb = 0.0, n = 0.0;
  for (size_t p = 0; p < mask.size(); ++p)
  {
    if (mask[p])
    {
      sa += a[p];
      sb += b[p];
      n += 1.0;
    }
  }
  if (n < 2.0)
  {
    return 0.0;
  }
  const double ma = sa / n, mb = sb / n;
  double       ab = 0.0, aa = 0.0, bb = 0.0;
  for (size_t p = 0; p < mask.size(); ++p)
  {
    if (mask[p])
    {
      ab += (a[p] - ma) * (b[p] - mb);
      aa += (a[p] - ma) * (a[p] - ma);
      bb += (b[p] - mb) * (b[p] - mb);
    }
  }
  return aa > 0.0 && bb > 0.0 ? ab / std::sqrt(aa * bb) : 0.0;
}

double
DRRImageSimilarity::MaskedGradientCorrelation(const float *                a,
                                              const float *                b,
                                              const std::vector<uint8_t> & mask,
                                              size_t                       columns)
{
  const size_t rows = mask.size() / columns;
  double       sum = 0.0;
  for (const bool alongColumns : { true, false })
  {
    const size_t         step = alongColumns ? 1 : columns;
    std::vector<float>   da(mask.size(), 0.0f), db(mask.size(), 0.0f);
    std::vector<uint8_t> inside(mask.size(), 0);
    for (size_t r = alongColumns ? 0 : 1; r + (alongColumns ? 0 : 1) < rows; ++r)
    {
      for (size_t c = alongColumns ? 1 : 0; c + (alongColumns ? 1 : 0) < columns; ++c)
      {
        const size_t p = r * columns + c;
        inside[p] = mask[p - step] & mask[p + step];
        da[p] = a[p + step] - a[p - step];
        db[p] = b[p + step] - b[p - step];
      }
    }
    sum += MaskedNormalizedCorrelation(da.data(), db.data(), inside);
  }
  return 0.5 * sum;
}

double
DRRImageSimilarity::Evaluate(const std::string &          metric,
                             const float *                a,
                             const float *                b,
                             const std::vector<uint8_t> & mask,
                             size_t                       columns)
{
  if (metric == "gc")
  {
    return MaskedGradientCorrelation(a, b, mask, columns);
  }
  if (metric == "ncc")
  {
    return MaskedNormalizedCorrelation(a, b, mask);
  }
  itkGenericExceptionMacro("unknown similarity metric '" << metric << "' (" << JoinMetricNames(" or ") << ")");
}
} // namespace itk
