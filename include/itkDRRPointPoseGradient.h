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
#ifndef itkDRRPointPoseGradient_h
#define itkDRRPointPoseGradient_h

#include "itkDRRPointCloud.h"
#include "itkDRRPointProjection.h"
#include "itkMatrix.h"
#include "itkMultiThreaderBase.h"
#include "PointBasedDRRExport.h"

namespace itk
{
/** \class DRRPointPoseGradient
 * \brief The backward pass of a kept-point DRR: how a weighted sum of its pixels changes as its points move in the
 * room, reduced to the twelve numbers that any pose whose Jacobian is affine in the point (rigid, similarity, affine)
 * needs.
 *
 * A bilinear render of a cloud (DRRPointRenderer::Render(cloud, ...)) is D_k = sum_i w_i g(y_i) s_k(u(y_i)): point i
 * at room position y_i (mm), weight w_i = M / (N a) times its sampler weight, perspective weight g (1 for a parallel
 * beam or the paper's count), detector position u(y) and the bilinear splat s_k of pixel k. For a weight image G
 * (pixels of the detector; G_k = dS/dD_k for a similarity S), Phi = sum_k G_k D_k, and
 *
 *   gamma_i = dPhi/dy_i = w_i [ G^(u_i) grad g(y_i) + g(y_i) J_u(y_i)^T grad G^(u_i) ]
 *
 * with G^(u) = sum_k G_k s_k(u) the bilinear interpolant of G (0 off the detector), read at the points exactly where
 * the forward pass splats them (the shared design, section 12). The pass returns Sum = sum_i gamma_i and Moment =
 * sum_i gamma_i (y_i - Reference)^T, Reference the room position of the volume's central index: for a pose whose
 * derivative is J(y) = J(Reference) + sum_a (y - Reference)_a B_a, the derivative of Phi is Sum . J(Reference) plus
 * the trace of Moment's product with the B_a (PointBasedDRRMetricv4 does that sum). It also returns Phi itself,
 * recomputed from the points: equal to sum_k G_k D_k of the forward render up to rounding.
 *
 * It is the exact derivative of the estimate (frozen noise), almost everywhere: the bilinear splat has kinks where a
 * point crosses a pixel's centre line, where the derivative jumps; points that cross the depth limits (behind the
 * source, beyond the detector, nearer than the render's minimum depth) add nothing, as in the render.
 *
 * Reproducible: every chunk of DRRPointRenderer::SamplesPerChunk points is summed in order, in double, and the chunks'
 * sums are added in chunk order, so the same cloud, projection and G give the same bits on any number of threads.
 *
 * \sa DRRPointRenderer, PointBasedDRRMetricv4, DRRImageSimilarity::EvaluateWithDerivative()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPointPoseGradient
{
public:
  /** A room point, mm. */
  using PointType = DRRPointProjection::PointType;
  /** A room vector. */
  using VectorType = DRRPointProjection::VectorType;
  /** Unbiased or PaperCount point weighting. */
  using WeightingEnum = PointBasedDRREnums::PointWeighting;

  /** What the backward pass returns. Units: Phi's (G's times the DRR's) per mm for Sum, Phi's for Moment. */
  struct Moments
  {
    PointType            Reference;             ///< room position of the volume's central index, mm
    VectorType           Sum{ 0.0 };            ///< sum_i dPhi/dy_i
    Matrix<double, 3, 3> Moment;                ///< sum_i dPhi/dy_i (y_i - Reference)^T
    double               Value{ 0.0 };          ///< Phi = sum_i w_i g(y_i) G^(u_i)
    uint64_t             PointsOnDetector{ 0 }; ///< points with a corner on the detector
  };

  /** The backward pass of the bilinear render of cloud for projection (whose minimum depth must be the render's,
   * DRRPointRenderer::Result::MinimumDepth) with the weight image pixelWeights (the projection's columns x rows,
   * columns fastest) and the point weighting of the render. */
  static Moments
  Compute(const DRRPointCloud &      cloud,
          const DRRPointProjection & projection,
          WeightingEnum              weighting,
          const double *             pixelWeights,
          MultiThreaderBase *        threader);
};
} // namespace itk

#endif
