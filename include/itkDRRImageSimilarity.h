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
#ifndef itkDRRImageSimilarity_h
#define itkDRRImageSimilarity_h

#include "itkPointBasedDRREnums.h"
#include "PointBasedDRRExport.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace itk
{
/** \class DRRImageSimilarity
 * \brief The similarities of a DRR and a real X-ray that PointBasedDRRRegistrationMethod maximizes, over a mask of
 * the pixels both cover.
 *
 * Both are blind to the X-ray's gain, offset and units (a real X-ray is no line integral):
 * - "ncc": the normalized cross-correlation of the two images;
 * - "gc": the gradient correlation (Penney et al. 1998), the mean of the NCCs of the two images' differences along
 *   the rows and along the columns: edges only, blind to the smooth content an X-ray has and a CT's DRR lacks (a table
 *   outside the CT's field, scatter, a heel effect).
 *
 * GetMetricNames() is the one list of the names, in the order of PointBasedDRREnums::Similarity: pbdrr register's help
 * and parsing are derived from it.
 *
 * EvaluateWithDerivative() also gives dS/da_p, the derivative with respect to every pixel of the DRR, in closed form:
 * for the NCC r = sum a'b' / sqrt(sum a'^2 sum b'^2) (a', b': minus their means over the field), dr/da_p =
 * b'_p / sqrt(sum a'^2 sum b'^2) - r a'_p / sum a'^2 on the field, 0 off it (the means' terms add up to 0); for the
 * gradient correlation, the same through the differences' adjoint. PointBasedDRRMetricv4 reads it at every kept point.
 *
 * Images are row-major buffers of columns x rows pixels; a mask holds 1 for a counted pixel, 0 otherwise.
 *
 * \sa PointBasedDRRRegistrationMethod
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRImageSimilarity
{
public:
  /** NormalizedCorrelation or GradientCorrelation. */
  using SimilarityEnum = PointBasedDRREnums::Similarity;

  /** The metric names, in the order of PointBasedDRREnums::Similarity: "ncc", "gc". */
  static const std::vector<std::string> &
  GetMetricNames();

  /** The similarity called name (one of GetMetricNames()). Throws itk::ExceptionObject, listing the names, for another.
   */
  static SimilarityEnum
  FromName(const std::string & name);

  /** The name of similarity ("ncc" or "gc"). */
  static const std::string &
  GetName(SimilarityEnum similarity);

  /** True if name is one of GetMetricNames(). */
  static bool
  IsMetricName(const std::string & name);

  /** The names joined by separator, e.g. "ncc or gc" for " or ". */
  static std::string
  JoinMetricNames(const std::string & separator);

  /** The normalized cross-correlation of a and b over the pixels where mask is 1 (mask.size() pixels): 0 if either is
   * constant there or fewer than 2 pixels count. */
  static double
  MaskedNormalizedCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask);

  /** The gradient correlation of a and b (columns wide, mask.size() / columns rows): the mean of the NCCs of their
   * central differences along the columns and along the rows, over the pixels whose two neighbours on that axis are
   * both in the mask. */
  static double
  MaskedGradientCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask, size_t columns);

  /** The metric called metric ("ncc" or "gc") of a and b (columns wide) over the mask. Throws itk::ExceptionObject
   * for another name. */
  static double
  Evaluate(const std::string &          metric,
           const float *                a,
           const float *                b,
           const std::vector<uint8_t> & mask,
           size_t                       columns);

  /** The similarity of a (a DRR, in double) and b (an X-ray), columns wide, over the mask (the same value as
   * Evaluate() up to rounding), and, unless derivative is null, its derivative with respect to every pixel of a:
   * derivative[p] = dS/da_p (mask.size() values; 0 for pixels that do not count). A constant image, or fewer than 2
   * pixels, gives 0 and a zero derivative: never NaN. */
  static double
  EvaluateWithDerivative(SimilarityEnum               similarity,
                         const double *               a,
                         const float *                b,
                         const std::vector<uint8_t> & mask,
                         size_t                       columns,
                         double *                     derivative);
};
} // namespace itk

#endif
