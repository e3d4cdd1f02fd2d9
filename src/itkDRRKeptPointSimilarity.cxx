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
#include "itkDRRKeptPointSimilarity.h"
#include "itkDRRExactRayIntegrator.h"
#include "itkDRRImageSimilarity.h"
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkMatrixOffsetTransformBase.h"
#include "vnl/vnl_inverse.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
/** One X-ray, prepared: its binned view, pixels and field, and the workers its renders reuse. */
struct DRRKeptPointSimilarity::View
{
  DRRProjectionGeometry::Pointer                       Geometry;
  std::vector<float>                                   XRay;
  std::vector<uint8_t>                                 Field;
  mutable std::shared_ptr<DRRPointRenderer::Workspace> Workspace;
};

namespace
{
/** The render of the kept points: bilinear (a splat with a derivative), unbiased. */
DRRPointRenderer::Settings
RenderSettings(const DRRKeptPointSimilarity::Settings & settings)
{
  DRRPointRenderer::Settings render;
  render.NumberOfSamples = settings.NumberOfSamples;
  render.Seed = settings.Seed;
  render.Kernel = settings.Kernel;
  render.Splat = PointBasedDRREnums::Splat::Bilinear;
  render.Weighting = PointBasedDRREnums::PointWeighting::Unbiased;
  return render;
}

/** The discrete Gaussian of sigma pixels, truncated at 3 sigma, summing to 1 (empty for sigma 0). */
std::vector<double>
GaussianKernel(double sigma)
{
  if (!(sigma > 0.0))
  {
    return {};
  }
  const int           radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  std::vector<double> kernel(2 * radius + 1);
  double              sum = 0.0;
  for (int k = -radius; k <= radius; ++k)
  {
    kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
    sum += kernel[k + radius];
  }
  for (double & value : kernel)
  {
    value /= sum;
  }
  return kernel;
}

/** Convolves image (columns x rows) in place with kernel along one axis, zero outside: a symmetric operator (its own
 * adjoint), so that the derivative goes back through the same call. */
void
Convolve(std::vector<double> &       image,
         size_t                      columns,
         size_t                      rows,
         const std::vector<double> & kernel,
         bool                        alongColumns)
{
  if (kernel.empty())
  {
    return;
  }
  const int64_t       radius = static_cast<int64_t>(kernel.size() / 2);
  const int64_t       length = static_cast<int64_t>(alongColumns ? columns : rows);
  const size_t        lines = alongColumns ? rows : columns;
  const size_t        step = alongColumns ? 1 : columns;
  std::vector<double> line(static_cast<size_t>(length));
  for (size_t l = 0; l < lines; ++l)
  {
    double * start = image.data() + (alongColumns ? l * columns : l);
    for (int64_t i = 0; i < length; ++i)
    {
      line[static_cast<size_t>(i)] = start[i * step];
    }
    for (int64_t i = 0; i < length; ++i)
    {
      double sum = 0.0;
      for (int64_t k = std::max<int64_t>(-radius, -i); k <= std::min<int64_t>(radius, length - 1 - i); ++k)
      {
        sum += kernel[static_cast<size_t>(k + radius)] * line[static_cast<size_t>(i + k)];
      }
      start[i * step] = sum;
    }
  }
}

/** Smooths a binned detector image by settings' Gaussian (sigma in mm at the detector), in place. */
void
Smooth(std::vector<double> & image, const DRRProjectionGeometry & geometry, double sigma)
{
  if (!(sigma > 0.0))
  {
    return;
  }
  const size_t columns = geometry.GetDetectorSize()[0], rows = geometry.GetDetectorSize()[1];
  Convolve(image, columns, rows, GaussianKernel(sigma / geometry.GetDetectorSpacing()[0]), true);
  Convolve(image, columns, rows, GaussianKernel(sigma / geometry.GetDetectorSpacing()[1]), false);
}

/** The field without the pixels whose smoothed value reads a pixel outside it (within the Gaussian's support): the
 * DRR is zero where no ray crosses the CT while the X-ray goes on, and that step, blurred into the field, would be an
 * edge of the DRR's own making. */
std::vector<uint8_t>
ErodeBySmoothing(const std::vector<uint8_t> & field, const DRRProjectionGeometry & geometry, double sigma)
{
  if (!(sigma > 0.0))
  {
    return field;
  }
  const int64_t columns = static_cast<int64_t>(geometry.GetDetectorSize()[0]);
  const int64_t rows = static_cast<int64_t>(geometry.GetDetectorSize()[1]);
  const int64_t reach[2] = { static_cast<int64_t>(GaussianKernel(sigma / geometry.GetDetectorSpacing()[0]).size() / 2),
                             static_cast<int64_t>(GaussianKernel(sigma / geometry.GetDetectorSpacing()[1]).size() /
                                                  2) };
  // Along the columns, then along the rows: a pixel stays if every pixel of its kernel's box is in the field.
  std::vector<uint8_t> along(field.size(), 0), eroded(field.size(), 0);
  for (int64_t r = 0; r < rows; ++r)
  {
    for (int64_t c = 0; c < columns; ++c)
    {
      bool inside = c - reach[0] >= 0 && c + reach[0] < columns;
      for (int64_t k = -reach[0]; inside && k <= reach[0]; ++k)
      {
        inside = field[r * columns + c + k] != 0;
      }
      along[r * columns + c] = inside ? 1 : 0;
    }
  }
  for (int64_t r = 0; r < rows; ++r)
  {
    for (int64_t c = 0; c < columns; ++c)
    {
      bool inside = r - reach[1] >= 0 && r + reach[1] < rows;
      for (int64_t k = -reach[1]; inside && k <= reach[1]; ++k)
      {
        inside = along[(r + k) * columns + c] != 0;
      }
      eroded[r * columns + c] = inside ? 1 : 0;
    }
  }
  return eroded;
}

using MatrixOffsetType = MatrixOffsetTransformBase<double, 3, 3>;
} // namespace

DRRKeptPointSimilarity::DRRKeptPointSimilarity() = default;
DRRKeptPointSimilarity::~DRRKeptPointSimilarity() = default;

void
DRRKeptPointSimilarity::GetLinearPart(const TransformType &            pose,
                                      DRRPointProjection::MatrixType & matrix,
                                      DRRPointProjection::VectorType & offset)
{
  if (const auto * matrixOffset = dynamic_cast<const MatrixOffsetType *>(&pose))
  {
    matrix = matrixOffset->GetMatrix();
    offset = matrixOffset->GetOffset();
    return;
  }
  if (!pose.IsLinear())
  {
    itkGenericExceptionMacro("the pose is a " << pose.GetNameOfClass()
                                              << ", not a linear transform: the kept points' derivative needs one "
                                                 "(Euler3DTransform, VersorRigid3DTransform, Similarity3DTransform, "
                                                 "AffineTransform, TranslationTransform, or a composite of them)");
  }
  // Any other linear transform (a translation, a composite of linear ones): x = A y + b read off four points.
  const TransformType::InputPointType origin{};
  const auto                          atOrigin = pose.TransformPoint(origin);
  for (unsigned int c = 0; c < 3; ++c)
  {
    TransformType::InputPointType unit{};
    unit[c] = 1.0;
    const auto image = pose.TransformPoint(unit);
    for (unsigned int r = 0; r < 3; ++r)
    {
      matrix[r][c] = image[r] - atOrigin[r];
    }
  }
  offset = atOrigin.GetVectorFromOrigin();
}

DRRProjectionGeometry::Pointer
DRRKeptPointSimilarity::BinnedGeometry(const DRRProjectionGeometry & geometry, unsigned int shrink)
{
  // A copy through the geometry file format, which round-trips every field.
  std::stringstream text;
  DRRProjectionGeometryFileIO::WriteToStream(text, &geometry);
  auto binned = DRRProjectionGeometry::New();
  DRRProjectionGeometryFileIO::ReadFromStream(text, binned);
  if (shrink <= 1)
  {
    return binned;
  }
  // Coarse pixel K covers the fine pixels shrink K .. shrink K + shrink - 1, so its centre is their mean.
  DRRProjectionGeometry::DetectorSizeType   size;
  DRRProjectionGeometry::DetectorVectorType spacing, offset;
  for (unsigned int d = 0; d < 2; ++d)
  {
    const double fine = static_cast<double>(geometry.GetDetectorSize()[d]);
    size[d] = std::max<SizeValueType>(1, geometry.GetDetectorSize()[d] / shrink);
    const double coarse = static_cast<double>(size[d]);
    spacing[d] = geometry.GetDetectorSpacing()[d] * shrink;
    offset[d] =
      geometry.GetDetectorOffset()[d] +
      (0.5 * (shrink - 1.0) - 0.5 * (fine - 1.0) + 0.5 * (coarse - 1.0) * shrink) * geometry.GetDetectorSpacing()[d];
  }
  binned->SetDetectorSize(size);
  binned->SetDetectorSpacing(spacing);
  binned->SetDetectorOffset(offset);
  return binned;
}

std::vector<float>
DRRKeptPointSimilarity::BinnedImage(const XRayImageType & image, unsigned int shrink)
{
  const auto         size = image.GetLargestPossibleRegion().GetSize();
  const size_t       columns = std::max<size_t>(1, size[0] / shrink), rows = std::max<size_t>(1, size[1] / shrink);
  const unsigned int block = static_cast<unsigned int>(std::min<size_t>(shrink, std::min(size[0], size[1])));
  std::vector<float> binned(columns * rows, 0.0f);
  const float *      in = image.GetBufferPointer();
  for (size_t r = 0; r < rows; ++r)
  {
    for (size_t c = 0; c < columns; ++c)
    {
      double sum = 0.0;
      for (unsigned int j = 0; j < block; ++j)
      {
        for (unsigned int i = 0; i < block; ++i)
        {
          sum += in[(r * shrink + j) * size[0] + c * shrink + i];
        }
      }
      binned[r * columns + c] = static_cast<float>(sum / (block * block));
    }
  }
  return binned;
}

std::vector<uint8_t>
DRRKeptPointSimilarity::CoveredField(const DRRProjectionGeometry &          geometry,
                                     const DRRPointProjection &             projection,
                                     const DRRAttenuationVolume::SizeType & volumeSize)
{
  // A slab test per pixel against the grid [-0.5, n - 0.5]^3, in the volume's continuous index.
  const auto           size = geometry.GetDetectorSize();
  std::vector<uint8_t> mask(size[0] * size[1], 0);
  const bool           parallel = !projection.IsPerspective();
  for (unsigned int row = 0; row < size[1]; ++row)
  {
    for (unsigned int column = 0; column < size[0]; ++column)
    {
      const auto start = geometry.GetRayStart(column, row);
      auto       end = geometry.GetPixelCenter(column, row);
      if (parallel)
      {
        end = end + (end - start); // the whole line: as far beyond the detector as the start is before it
      }
      double a[3], b[3];
      projection.RoomToIndex(start, a);
      projection.RoomToIndex(end, b);
      double enter = 0.0, exit = 1.0;
      for (unsigned int k = 0; k < 3 && enter <= exit; ++k)
      {
        const double low = -0.5, high = static_cast<double>(volumeSize[k]) - 0.5, d = b[k] - a[k];
        if (std::abs(d) < 1e-300)
        {
          exit = (a[k] < low || a[k] > high) ? -1.0 : exit;
          continue;
        }
        const double t1 = (low - a[k]) / d, t2 = (high - a[k]) / d;
        enter = std::max(enter, std::min(t1, t2));
        exit = std::min(exit, std::max(t1, t2));
      }
      mask[row * size[0] + column] = enter < exit ? 1 : 0;
    }
  }
  return mask;
}

void
DRRKeptPointSimilarity::Prepare(const DRRAttenuationVolume & model,
                                ModifiedTimeType             modelTime,
                                DRRPointSampler &            sampler,
                                const std::vector<XRay> &    xrays,
                                const Settings &             settings,
                                const TransformType &        pose,
                                MultiThreaderBase *          threader)
{
  if (settings.NumberOfSamples == 0 && settings.ExactRaysPerPixelSide == 0)
  {
    itkGenericExceptionMacro("the number of samples is 0: the kept points' DRRs need at least one point");
  }
  if (settings.ShrinkFactor == 0)
  {
    itkGenericExceptionMacro("the detector shrink factor is 0: give 1 (full resolution) or more");
  }
  if (!(settings.SmoothingSigma >= 0.0) || !std::isfinite(settings.SmoothingSigma))
  {
    itkGenericExceptionMacro("the smoothing sigma is " << settings.SmoothingSigma << " mm: give 0 (none) or more");
  }
  if (xrays.empty())
  {
    itkGenericExceptionMacro("no X-ray: give at least one (AddXRay())");
  }
  const auto volumeSize = model.GetSize();
  if (volumeSize[0] == 0 || volumeSize[1] == 0 || volumeSize[2] == 0)
  {
    itkGenericExceptionMacro("the volume is empty (" << volumeSize[0] << " x " << volumeSize[1] << " x "
                                                     << volumeSize[2] << " voxels)");
  }
  DRRPointProjection::MatrixType matrix;
  DRRPointProjection::VectorType offset;
  GetLinearPart(pose, matrix, offset);
  m_Views.clear();

  // The X-rays first (cheap, and the commonest mistakes), into views that replace the old ones only when all is
  // ready: a Prepare() that throws leaves nothing prepared.
  std::vector<View> views;
  for (unsigned int x = 0; x < xrays.size(); ++x)
  {
    const XRay & xray = xrays[x];
    if (!xray.Image || !xray.Geometry)
    {
      itkGenericExceptionMacro("X-ray " << x << " has no image or no geometry");
    }
    xray.Geometry->VerifyGeometry();
    const auto size = xray.Image->GetLargestPossibleRegion().GetSize();
    const auto detector = xray.Geometry->GetDetectorSize();
    if (detector[0] != size[0] || detector[1] != size[1])
    {
      itkGenericExceptionMacro("X-ray " << x << " is " << size[0] << " x " << size[1] << " pixels, its view "
                                        << detector[0] << " x " << detector[1]);
    }
    const float * pixels = xray.Image->GetBufferPointer();
    if (!pixels)
    {
      itkGenericExceptionMacro("X-ray " << x << " has no pixels in memory (Update() it first)");
    }
    const size_t count = size[0] * size[1];
    const auto   notFinite = std::find_if(pixels, pixels + count, [](float v) { return !std::isfinite(v); });
    if (notFinite != pixels + count)
    {
      itkGenericExceptionMacro("X-ray " << x << " has a pixel that is not a finite number (pixel "
                                        << (notFinite - pixels) << ": " << *notFinite << ")");
    }
    View view;
    view.Geometry = BinnedGeometry(*xray.Geometry, settings.ShrinkFactor);
    std::vector<float>  binned = BinnedImage(*xray.Image, settings.ShrinkFactor);
    std::vector<double> smoothed(binned.begin(), binned.end());
    Smooth(smoothed, *view.Geometry, settings.SmoothingSigma);
    view.XRay.assign(smoothed.begin(), smoothed.end());
    const DRRPointProjection   projection(*view.Geometry, model, matrix, offset);
    const std::vector<uint8_t> seen = CoveredField(*view.Geometry, projection, volumeSize);
    view.Field = ErodeBySmoothing(seen, *view.Geometry, settings.SmoothingSigma);
    const size_t seenPixels = static_cast<size_t>(std::count(seen.begin(), seen.end(), uint8_t{ 1 }));
    const size_t covered = static_cast<size_t>(std::count(view.Field.begin(), view.Field.end(), uint8_t{ 1 }));
    if (seenPixels < 3)
    {
      itkGenericExceptionMacro("X-ray " << x << "'s view misses the volume at the start pose (" << seenPixels
                                        << " pixels of its binned detector see it): no overlap to compare");
    }
    if (covered < 3)
    {
      // The field is eroded by the smoothing's support (its border would pull the pose): a small field and a large
      // smoothing leave nothing, which is the smoothing's doing, not the view's.
      itkGenericExceptionMacro("X-ray " << x << "'s field of the volume (" << seenPixels
                                        << " pixels of its binned detector) is eroded away by the smoothing of "
                                        << settings.SmoothingSigma << " mm (" << covered
                                        << " pixels left): smooth less at this level");
    }
    float low = std::numeric_limits<float>::infinity(), high = -low;
    for (size_t p = 0; p < view.Field.size(); ++p)
    {
      if (view.Field[p])
      {
        low = std::min(low, view.XRay[p]);
        high = std::max(high, view.XRay[p]);
      }
    }
    if (!(high > low))
    {
      itkGenericExceptionMacro("X-ray " << x << " is constant (" << low
                                        << ") where it sees the volume: no similarity can be measured");
    }
    view.Workspace = DRRPointRenderer::MakeWorkspace();
    views.push_back(std::move(view));
  }

  // The points: drawn again only when what they are drawn from changed (none for the exact projector).
  const bool newModel = &model != m_Model || modelTime != m_CloudModelTime || &sampler != m_CloudSampler ||
                        sampler.GetMTime() != m_CloudSamplerTime;
  if (newModel)
  {
    m_Cloud = nullptr;
    m_Model = nullptr;
  }
  if (settings.ExactRaysPerPixelSide > 0)
  {
    const DRRExactRayIntegrator check(model, settings.Kernel); // throws for a kernel without an exact projector
    if (!(model.ComputeTotalMass() > 0.0))
    {
      itkGenericExceptionMacro("the volume is all air (attenuation mass 0): there is nothing to register");
    }
  }
  else
  {
    if (!m_Model)
    {
      sampler.Initialize(model);
      m_CloudSamplerTime = sampler.GetMTime();
    }
    if (!(sampler.GetTotalMass() > 0.0))
    {
      itkGenericExceptionMacro("the volume is all air (attenuation mass 0): there is nothing to register");
    }
    if (!m_Cloud || settings.NumberOfSamples != m_Settings.NumberOfSamples || settings.Seed != m_Settings.Seed ||
        settings.Kernel != m_Settings.Kernel)
    {
      m_Cloud = nullptr; // free the old points before drawing new ones
      m_Cloud = DRRPointRenderer::Draw(model, sampler, RenderSettings(settings), threader, nullptr);
      ++m_NumberOfDraws;
    }
    m_Model = &model; // the sampler is ready for it
  }
  m_PreparedModel = &model;
  m_CloudModelTime = modelTime;
  m_CloudSampler = &sampler;
  m_Settings = settings;

  m_Views = std::move(views);
}

double
DRRKeptPointSimilarity::Evaluate(const TransformType &     pose,
                                 DerivativeType *          derivative,
                                 std::vector<ViewResult> * views,
                                 MultiThreaderBase *       threader) const
{
  const bool exact = m_Settings.ExactRaysPerPixelSide > 0;
  if ((!m_Cloud && !exact) || m_Views.empty() || !m_PreparedModel)
  {
    itkGenericExceptionMacro("the kept-point similarity is not prepared (Prepare(), or the metric's Initialize())");
  }
  if (exact && derivative)
  {
    itkGenericExceptionMacro("the exact projector's DRRs have no derivative here: use a derivative-free optimizer "
                             "(PowellOptimizerv4, AmoebaOptimizerv4, OnePlusOneEvolutionaryOptimizerv4) or the kept "
                             "points");
  }
  DRRPointProjection::MatrixType matrix;
  DRRPointProjection::VectorType offset;
  GetLinearPart(pose, matrix, offset);
  const unsigned int numberOfParameters = pose.GetNumberOfParameters();
  if (derivative)
  {
    derivative->SetSize(numberOfParameters);
    derivative->Fill(0.0);
  }
  if (views)
  {
    views->assign(m_Views.size(), ViewResult{});
  }
  const DRRPointRenderer::Settings render = RenderSettings(m_Settings);
  // A^-1 and the parameter Jacobian's affine form about the reference point, from the first view's moments.
  const vnl_matrix_fixed<double, 3, 3>        inverse = vnl_inverse(matrix.GetVnlMatrix());
  TransformType::JacobianType                 atReference, atStep;
  std::vector<vnl_matrix_fixed<double, 3, 3>> steps; // B_j: dJ_j/dy, one per parameter
  double                                      sum = 0.0;
  std::vector<double>                         weights;
  for (size_t v = 0; v < m_Views.size(); ++v)
  {
    const View &             view = m_Views[v];
    DRRPointProjection       projection(*view.Geometry, *m_PreparedModel, matrix, offset);
    DRRPointRenderer::Result result;
    if (exact)
    {
      const DRRExactRayIntegrator integrator(*m_PreparedModel, m_Settings.Kernel);
      result.LineIntegral =
        integrator.RenderProjection(projection, m_Settings.ExactRaysPerPixelSide, threader, nullptr);
    }
    else
    {
      result = DRRPointRenderer::Render(*m_Cloud, projection, render, threader, nullptr, view.Workspace.get());
    }
    std::vector<double> drr = std::move(result.LineIntegral);
    Smooth(drr, *view.Geometry, m_Settings.SmoothingSigma);
    weights.assign(derivative ? drr.size() : 0, 0.0);
    const double similarity = DRRImageSimilarity::EvaluateWithDerivative(m_Settings.Similarity,
                                                                         drr.data(),
                                                                         view.XRay.data(),
                                                                         view.Field,
                                                                         view.Geometry->GetDetectorSize()[0],
                                                                         derivative ? weights.data() : nullptr);
    sum += similarity;
    if (views)
    {
      (*views)[v].Similarity = similarity;
      (*views)[v].DRR = std::move(drr);
    }
    if (!derivative)
    {
      continue;
    }
    Smooth(weights, *view.Geometry, m_Settings.SmoothingSigma); // the smoothing's adjoint is itself
    projection.SetMinimumDepth(result.MinimumDepth);            // drop what the render dropped
    const DRRPointPoseGradient::Moments moments = DRRPointPoseGradient::Compute(
      *m_Cloud, projection, PointBasedDRREnums::PointWeighting::Unbiased, weights.data(), threader);
    if (steps.empty())
    {
      // J(y) = J(ref) + sum_a (y - ref)_a B_a: the Jacobian of a MatrixOffsetTransformBase is affine in the point.
      pose.ComputeJacobianWithRespectToParameters(moments.Reference, atReference);
      steps.resize(numberOfParameters);
      for (unsigned int a = 0; a < 3; ++a)
      {
        auto stepped = moments.Reference;
        stepped[a] += 1.0;
        pose.ComputeJacobianWithRespectToParameters(stepped, atStep);
        for (unsigned int j = 0; j < numberOfParameters; ++j)
        {
          for (unsigned int r = 0; r < 3; ++r)
          {
            steps[j](r, a) = atStep(r, j) - atReference(r, j);
          }
        }
      }
    }
    // dPhi/dtheta_j = -(A^-T Sum) . J_j(ref) - sum_rc (A^-1 B_j)_rc Moment_rc - Phi tr(A^-1 B_j): the points move by
    // dy = -A^-1 dT, and the mass they stand for scales as 1 / |det A|.
    double h[3];
    for (unsigned int r = 0; r < 3; ++r)
    {
      h[r] = inverse(0, r) * moments.Sum[0] + inverse(1, r) * moments.Sum[1] + inverse(2, r) * moments.Sum[2];
    }
    for (unsigned int j = 0; j < numberOfParameters; ++j)
    {
      const vnl_matrix_fixed<double, 3, 3> inverseStep = inverse * steps[j];
      double                               d = 0.0, trace = 0.0;
      for (unsigned int r = 0; r < 3; ++r)
      {
        d -= h[r] * atReference(r, j);
        trace += inverseStep(r, r);
        for (unsigned int c = 0; c < 3; ++c)
        {
          d -= inverseStep(r, c) * moments.Moment[r][c];
        }
      }
      (*derivative)[j] += d - moments.Value * trace;
    }
  }
  const double count = static_cast<double>(m_Views.size());
  if (derivative)
  {
    *derivative /= count;
  }
  return sum / count;
}

const DRRProjectionGeometry *
DRRKeptPointSimilarity::GetBinnedGeometry(unsigned int index) const
{
  return index < m_Views.size() ? m_Views[index].Geometry.GetPointer() : nullptr;
}

const std::vector<float> &
DRRKeptPointSimilarity::GetBinnedXRay(unsigned int index) const
{
  return m_Views.at(index).XRay;
}

const std::vector<uint8_t> &
DRRKeptPointSimilarity::GetField(unsigned int index) const
{
  return m_Views.at(index).Field;
}

const DRRPointCloud *
DRRKeptPointSimilarity::GetPointCloud() const
{
  return m_Cloud.GetPointer();
}

unsigned int
DRRKeptPointSimilarity::GetNumberOfDraws() const
{
  return m_NumberOfDraws;
}
} // namespace itk
