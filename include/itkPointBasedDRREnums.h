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
#ifndef itkPointBasedDRREnums_h
#define itkPointBasedDRREnums_h

#include "PointBasedDRRExport.h"
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

namespace itk
{
/** \class PointBasedDRREnums
 * \brief Enumerations shared by the PointBasedDRR filters, geometry and transfer functions.
 *
 * Each enumeration prints its value's name with operator<<.
 *
 * \sa PointBasedDRRImageFilter, ExactDRRImageFilter, DRRProjectionGeometry, DRRTransferFunction
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT PointBasedDRREnums
{
public:
  /** \brief Beam model. Perspective integrates from the source to the pixel; parallel integrates the whole
   * line through the pixel along the detector normal; localizer is a fan across the table (columns) and parallel along
   * it (rows): a CT scout, whose source moves with the table. */
  enum class Projection : uint8_t
  {
    /** Rays from the source S to every pixel (the default). */
    Perspective,
    /** Rays along -n, one line through every pixel; no source. */
    Parallel,
    /** A CT localizer: rays from the source, moved along the rows' direction v to the pixel's row, to the pixel. */
    Localizer
  };

  /** \brief Where inside its voxel a point is drawn, i.e. which continuous attenuation model is rendered.
   * Box: uniform in the voxel (piecewise-constant model, exact reference: Siddon).
   * Tent: voxel centre plus a triangular offset of +-1 voxel per axis (trilinear model of the volume padded
   * with one layer of zero voxels; exact reference: dual-grid trilinear integral). */
  enum class ReconstructionKernel : uint8_t
  {
    /** Uniform in the voxel: the piecewise-constant model (the default). */
    Box,
    /** Voxel centre plus a triangular offset of +-1 voxel per axis: the trilinear model. */
    Tent
  };

  /** \brief How a projected point is deposited on the detector.
   * Nearest: the pixel containing it (unbiased for the pixel-area average).
   * Bilinear: the four nearest pixel centres with bilinear weights (lower variance; its expectation is the
   * pixel-area average blurred by a one-pixel tent, a blur that is part of its measured error). */
  enum class Splat : uint8_t
  {
    /** The pixel that contains the projected point (the default). */
    Nearest,
    /** The four nearest pixel centres, with bilinear weights. */
    Bilinear
  };

  /** \brief What the output pixels hold. LineIntegral (default): the dimensionless line integral of mu;
   * Transmission: exp(-line integral); Gray8 / Gray16: the line integral windowed onto [0, 255] or
   * [0, 65535] (the paper's quantization step; bright = attenuating, as on a radiograph). */
  enum class OutputMode : uint8_t
  {
    /** The line integral of mu (mm times 1/mm: dimensionless), the default. */
    LineIntegral,
    /** exp(-line integral), in [0, 1]. */
    Transmission,
    /** Gray levels 0 to 255 over the window. */
    Gray8,
    /** Gray levels 0 to 65535 over the window. */
    Gray16
  };

  /** \brief How input voxel values become linear attenuation mu (1/mm).
   * Natural: mu = mu_water(E) * max(0, 1 + HU / 1000);
   * PiecewiseLinear: user-given (value, mu) pairs; Identity: the input already is mu in 1/mm;
   * Materials: a DRRMaterialTable's material and density of the HU, at the effective energy. */
  enum class TransferFunction : uint8_t
  {
    /** mu = mu_water(E) * max(0, 1 + HU / 1000), for CT in HU (the default). */
    Natural,
    /** Linear between user-given (value, mu) pairs. */
    PiecewiseLinear,
    /** The input is mu in 1/mm. */
    Identity,
    /** HU -> (material, density) by a DRRMaterialTable; mu = density x (mu/rho)_material(E_ref) (1/mm). */
    Materials
  };

  /** \brief Perspective weighting of each point. Unbiased (default) gives the pixel-area average line
   * integral; PaperCount counts every point with weight 1, as in the paper, which is biased by the
   * magnification in perspective. */
  enum class PointWeighting : uint8_t
  {
    /** The perspective weight (SID / z)^2 sqrt(SID^2 + u^2 + v^2) / SID of each point (the default): the pixel-area
     * average line integral, without bias. */
    Unbiased,
    /** Weight 1 for every point, as in the paper: biased by the magnification in perspective. */
    PaperCount
  };

  /** \brief How alike a DRR and an X-ray are, over the pixels both cover (DRRImageSimilarity): blind to the X-ray's
   * gain, offset and units, not to its sign. Their names ("ncc", "gc") are DRRImageSimilarity::GetMetricNames(). */
  enum class Similarity : uint8_t
  {
    /** The normalized cross-correlation of the two images. */
    NormalizedCorrelation,
    /** The gradient correlation (Penney et al. 1998): the mean of the NCCs of the images' differences along the rows
     * and along the columns (the default of the registration). */
    GradientCorrelation
  };

  /** The registered names of a policy family (TEnum: Projection, ReconstructionKernel or Splat), lower case, in
   * registration order, the default first: `perspective`, `parallel`, `localizer`; `box`, `tent`; `nearest`,
   * `bilinear`. The engine registers each policy once (DRRPolicies); what lists them (pbdrr's options and help, the
   * tests) asks here. */
  template <typename TEnum>
  static std::vector<std::string>
  GetNames();

  /** The registered name of an enumerator (`tent`; operator<< prints its enumerator name, `Tent`). @{ */
  static std::string
  GetName(Projection value);
  static std::string
  GetName(ReconstructionKernel value);
  static std::string
  GetName(Splat value);
  /** @} */

  /** Sets value to the enumerator registered as name and returns true; false (value untouched) if none is. */
  template <typename TEnum>
  static bool
  FromName(const std::string & name, TEnum & value);

  /** True for a beam whose rays start at a source (perspective, localizer); false for the parallel beam. */
  static bool
  HasSource(Projection value);

  /** The name of the exact projector of a kernel's attenuation model (`siddon` for box, `trilinear` for tent), or ""
   * if it has none. */
  static std::string
  GetExactReferenceName(ReconstructionKernel value);
};

/** Writes the name of the enumerator (e.g. `Perspective`). @{ */
PointBasedDRR_EXPORT std::ostream &
                     operator<<(std::ostream & out, const PointBasedDRREnums::Projection value);
PointBasedDRR_EXPORT std::ostream &
                     operator<<(std::ostream & out, const PointBasedDRREnums::ReconstructionKernel value);
PointBasedDRR_EXPORT std::ostream &
                     operator<<(std::ostream & out, const PointBasedDRREnums::Splat value);
PointBasedDRR_EXPORT std::ostream &
                     operator<<(std::ostream & out, const PointBasedDRREnums::OutputMode value);
PointBasedDRR_EXPORT std::ostream &
                     operator<<(std::ostream & out, const PointBasedDRREnums::TransferFunction value);
PointBasedDRR_EXPORT std::ostream &
                     operator<<(std::ostream & out, const PointBasedDRREnums::PointWeighting value);
PointBasedDRR_EXPORT std::ostream &
                     operator<<(std::ostream & out, const PointBasedDRREnums::Similarity value);
/** @} */
} // namespace itk

#endif
