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
#ifndef itkDRRKeptPointSimilarity_h
#define itkDRRKeptPointSimilarity_h

#include "itkArray.h"
#include "itkDRRAttenuationVolume.h"
#include "itkDRRPointCloud.h"
#include "itkDRRPointPoseGradient.h"
#include "itkDRRPointRenderer.h"
#include "itkDRRPointSampler.h"
#include "itkDRRProjectionGeometry.h"
#include "itkImage.h"
#include "itkMultiThreaderBase.h"
#include "itkPointBasedDRREnums.h"
#include "itkTransform.h"
#include "PointBasedDRRExport.h"

#include <memory>
#include <vector>

namespace itk
{
/** \class DRRKeptPointSimilarity
 * \brief The compiled engine of PointBasedDRRMetricv4: the similarity of kept-point DRRs and X-rays at a pose, and its
 * analytic derivative with respect to the pose's parameters.
 *
 * It holds the kept points (drawn once, over the whole volume, and re-projected at every pose: frozen noise), and per
 * X-ray its view and image binned by the detector shrink factor, smoothed alike, and the field both cover. At a pose
 * (a linear room-to-volume transform, as PointBasedDRRImageFilter::SetTransform() takes) it renders every view with the
 * bilinear splat (DRRPointRenderer::Render(cloud, ...)), computes the similarity S_v of each with its X-ray and dS_v/dD
 * in closed form (DRRImageSimilarity::EvaluateWithDerivative()), and runs the backward pass
 * (DRRPointPoseGradient::Compute()) with that image as its weights. The derivative with respect to the parameters
 * theta of the transform T (room to volume: a point fixed in the volume is at y = T^-1(x) in the room, dy/dtheta =
 * -A^-1 dT/dtheta(y), A the transform's matrix) follows from the pass's moments and T's parameter Jacobian, which
 * is affine in the point for every linear transform (rigid, similarity, affine, translation): four evaluations of
 * ComputeJacobianWithRespectToParameters() per pose. A transform that scales also scales the mass the points stand
 * for (1 / |det A|), whose derivative is added.
 *
 * The value is the mean similarity over the X-rays; a value and its derivative cost a forward render and a backward
 * pass per X-ray, whatever the number of parameters.
 *
 * What the derivative is of: the kept points' bilinear render, exactly (its noise is frozen with the points), almost
 * everywhere (the splat has kinks at the pixels' centre lines). The smoothing is a symmetric Gaussian with zero
 * padding, its own adjoint; the field then leaves out the pixels whose smoothed value reads a pixel outside it (a DRR
 * is zero where no ray crosses the CT, an X-ray goes on: their step, blurred in, would be an edge of the DRR's own
 * making). The field is fixed at Prepare() (a piecewise-constant function of the pose, whose
 * derivative is 0): within one Prepare(), the value is continuous in the pose. There is no control variate: its coarse
 * image is a ray trace per pose, which is what kept points avoid, and its derivative lives on the coarse blocks' faces.
 *
 * With Settings::ExactRaysPerPixelSide, the DRRs are the exact projector's (no points are drawn) and there is no
 * derivative: a reference for derivative-free optimizers.
 *
 * \sa PointBasedDRRMetricv4, DRRPointPoseGradient, DRRImageSimilarity
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRKeptPointSimilarity
{
public:
  /** An X-ray: a 2D image of float. */
  using XRayImageType = Image<float, 2>;
  /** The pose: a transform from the room to the volume's physical frame. */
  using TransformType = Transform<double, 3, 3>;
  /** NormalizedCorrelation or GradientCorrelation. */
  using SimilarityEnum = PointBasedDRREnums::Similarity;
  /** Box or Tent reconstruction kernel. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;
  /** The derivative with respect to the transform's parameters. */
  using DerivativeType = Array<double>;

  /** What to render and compare. */
  struct Settings
  {
    SimilarityEnum Similarity{ SimilarityEnum::GradientCorrelation }; ///< ncc or gc
    uint64_t       NumberOfSamples{ 1000000 };                        ///< kept points N
    uint64_t       Seed{ 0 };                                         ///< of the points
    KernelEnum     Kernel{ KernelEnum::Box };                         ///< where in its voxel a point goes
    unsigned int   ShrinkFactor{ 1 };     ///< detector binning: shrink x shrink pixels per pixel
    double         SmoothingSigma{ 0.0 }; ///< Gaussian on the binned detector, mm at the detector (0: none)
    /** 0: the kept points (with a derivative); k >= 1: the exact projector of the kernel's model instead, k x k rays
     * per pixel (DRRExactRayIntegrator: no noise, no derivative, for derivative-free optimizers). */
    unsigned int ExactRaysPerPixelSide{ 0 };
  };

  /** One X-ray: its image and view (the view's detector size is the image's size). */
  struct XRay
  {
    XRayImageType::ConstPointer         Image;    ///< its pixels (columns x rows), any gain and offset
    DRRProjectionGeometry::ConstPointer Geometry; ///< its view
  };

  /** What one evaluation found for one X-ray. */
  struct ViewResult
  {
    double              Similarity{ 0.0 }; ///< S_v
    std::vector<double> DRR;               ///< the rendered (and smoothed) DRR on the binned detector, line integrals
  };

  DRRKeptPointSimilarity();
  ~DRRKeptPointSimilarity();

  /** Makes everything ready for Evaluate(): checks the X-rays (finite, not constant on their field), draws the points
   * if the model, the sampler, the seed, the kernel or the number of samples changed since the last draw, bins and
   * smooths the X-rays and fixes each one's field at the pose (room to volume). Throws ExceptionObject for an empty
   * or all-air model, zero samples, no X-ray, an X-ray whose size is not its view's, whose pixels are not all finite,
   * whose view misses the volume at the pose, or that is constant on its field, a shrink factor of 0 or a negative
   * smoothing. */
  void
  Prepare(const DRRAttenuationVolume & model,
          ModifiedTimeType             modelTime,
          DRRPointSampler &            sampler,
          const std::vector<XRay> &    xrays,
          const Settings &             settings,
          const TransformType &        pose,
          MultiThreaderBase *          threader);

  /** The mean similarity over the X-rays at the pose and, unless derivative is null, its derivative with respect to
   * the pose's parameters (d mean S / d theta, not negated), on the threads of threader (the same bits on any number).
   * views, unless null, gets each X-ray's similarity and DRR. Throws ExceptionObject if Prepare() was not called, for
   * a transform that is not linear, or for a derivative of the exact projector's DRRs. */
  double
  Evaluate(const TransformType &     pose,
           DerivativeType *          derivative,
           std::vector<ViewResult> * views,
           MultiThreaderBase *       threader) const;

  /** The binned view of X-ray index (after Prepare()). */
  const DRRProjectionGeometry *
  GetBinnedGeometry(unsigned int index) const;

  /** The binned, smoothed pixels of X-ray index (after Prepare()). */
  const std::vector<float> &
  GetBinnedXRay(unsigned int index) const;

  /** The field of X-ray index on its binned detector: 1 where the pixel counts (after Prepare()). */
  const std::vector<uint8_t> &
  GetField(unsigned int index) const;

  /** The kept points (null before Prepare()). */
  const DRRPointCloud *
  GetPointCloud() const;

  /** The number of draws of the kept points so far. */
  unsigned int
  GetNumberOfDraws() const;

  /** The room-to-volume matrix and offset of a linear transform (a MatrixOffsetTransformBase's own, or read off four
   * points); throws ExceptionObject, naming it, for a transform that is not linear (its parameter Jacobian would not be
   * affine in the point). */
  static void
  GetLinearPart(const TransformType &            pose,
                DRRPointProjection::MatrixType & matrix,
                DRRPointProjection::VectorType & offset);

  /** The view binned shrink x shrink (coarse pixel K covers fine pixels shrink K .. shrink K + shrink - 1; a last
   * partial block is left out), the same view for shrink 1. */
  static DRRProjectionGeometry::Pointer
  BinnedGeometry(const DRRProjectionGeometry & geometry, unsigned int shrink);

  /** The image binned as BinnedGeometry() bins its view: block means. */
  static std::vector<float>
  BinnedImage(const XRayImageType & image, unsigned int shrink);

  /** The pixels whose rays cross the volume's grid [-0.5, n - 0.5]^3 (continuous index) for the projection: the field
   * a DRR and an X-ray both cover. */
  static std::vector<uint8_t>
  CoveredField(const DRRProjectionGeometry &          geometry,
               const DRRPointProjection &             projection,
               const DRRAttenuationVolume::SizeType & volumeSize);

private:
  struct View;
  std::vector<View>            m_Views;
  DRRPointCloud::Pointer       m_Cloud;
  Settings                     m_Settings;
  const DRRAttenuationVolume * m_Model{ nullptr };         // the model the sampler was initialized for
  const DRRAttenuationVolume * m_PreparedModel{ nullptr }; // the model of the last Prepare()
  ModifiedTimeType             m_CloudModelTime{ 0 };
  ModifiedTimeType             m_CloudSamplerTime{ 0 };
  const DRRPointSampler *      m_CloudSampler{ nullptr };
  unsigned int                 m_NumberOfDraws{ 0 };
};
} // namespace itk

#endif
