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
#ifndef pbdrrRegistration_h
#define pbdrrRegistration_h

#include "pbdrrVolumeLoader.h"

#include "itkDRRProjectionGeometry.h"
#include "itkEuler3DTransform.h"
#include "itkImage.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pbdrr
{
/** An X-ray to register to: its image (2D, any intensity: bright bone or dark; MONOCHROME1 is inverted on reading) and
 * its view, whose pixel grid is the image's. */
struct XRay
{
  itk::Image<float, 2>::Pointer       Image;
  itk::DRRProjectionGeometry::Pointer Geometry;
  std::string                         Description;
};

/** Reads an X-ray: a CT localizer's DICOM file with its view from its header (ReadLocalizerView), or any 2D image with
 * a view from a geometry file (XRayViewOfFile()) or a projection matrix file (one of the two, not both). Throws
 * std::runtime_error if the image is not 2D, its size is not the view's, or a localizer's header does not give its
 * view. */
XRay
ReadXRay(const std::string &       image,
         const std::string &       geometryFile,
         const std::string &       matrixFile,
         const itk::ImageBase<3> * volume = nullptr);

/** The view of a geometry file, built as pbdrr's single view of `--geometry FILE` is (MakeView(): the defaults, 512 x
 * 512 pixels of 1.2 mm and the isocenter at the centre of volume, the room origin for a null volume; then the file),
 * so that the DRR of a registration is the single view's at the found pose. */
itk::DRRProjectionGeometry::Pointer
XRayViewOfFile(const std::string & geometryFile, const itk::ImageBase<3> * volume);

/** What a registration does: the rigid pose of the CT that makes its DRRs most like the X-rays.
 *
 * The pose is the CT moved in the room: x -> R (x - c) + c + t, c the centre of the CT's grid, R =
 * itk::Euler3DTransform's rotation of the angles (rx, ry, rz) (about z, then x, then y); identity is where the CT's own
 * frame of reference puts it. The similarity (Metric) is the gradient correlation (default) or the normalized
 * cross-correlation (NCC) of DRR and X-ray over the pixels whose rays cross the CT's grid (the field both cover),
 * averaged over the X-rays: both ignore the X-ray's gain, offset and units. Powell's method (itk::PowellOptimizer,
 * derivative-free) maximizes it on each level of a multi-resolution schedule (the detector binned shrink x shrink, the
 * X-ray block-averaged alike). */
struct RegistrationSettings
{
  std::array<double, 6> StartPose{}; // tx ty tz (mm) rx ry rz (degrees)
  std::vector<unsigned> Shrink{ 2, 1 };
  bool                  Exact{ false }; // the exact Siddon projector instead of kept points
  /** The exact projector's rays per pixel side: a pixel's value is the average of k x k rays, as a detector pixel
   * integrates (one ray samples a point: on sharp edges its NCC optimum is off by tenths of a degree). */
  unsigned ExactRaysPerSide{ 2 };
  /** The similarity: "ncc" (normalized cross-correlation of the images) or "gc" (gradient correlation: the mean of the
   * NCCs of the two images' row and column differences, Penney et al. 1998: edges only, blind to the smooth content an
   * X-ray has and a CT's DRR lacks, such as a table outside the CT's field, scatter or a heel effect). */
  std::string Metric{ "gc" };
  uint64_t    Samples{ 4000000 };
  uint64_t    Seed{ 0 };
  double      MaxSeconds{ 0.0 }; // 0: no limit
  unsigned    Threads{ 0 };
  bool        Verbose{ false };
};

/** The outcome of a registration. */
struct RegistrationResult
{
  std::array<double, 6>                      Pose{}; // tx ty tz (mm) rx ry rz (degrees)
  double                                     StartSimilarity{ 0.0 };
  double                                     Similarity{ 0.0 }; // NCC at full resolution, mean over the X-rays
  unsigned                                   Evaluations{ 0 };
  double                                     Seconds{ 0.0 };
  bool                                       StoppedByTime{ false };
  std::vector<itk::Image<float, 2>::Pointer> FinalDRRs; // at full resolution, one per X-ray
  std::vector<std::vector<uint8_t>>          Masks;     // the field both cover, per X-ray (1: counted)
};

/** For a view set from a projection matrix: throws std::runtime_error if the volume, moved by up to
 * marginInMillimeters, reaches beyond the detector plane, where the rays end (SID = fx du: a pixel pitch du too small
 * for the matrix's focal length fx puts the detector inside the volume, and the DRR would be cut or empty). Names the
 * pitch that is needed. */
void
CheckDetectorBeyondVolume(const itk::DRRProjectionGeometry * geometry,
                          const itk::ImageBase<3> *          volume,
                          double                             marginInMillimeters,
                          const std::string &                flag);

/** The rigid pose tx ty tz (mm) rx ry rz (degrees) of the CT in the room, as RegistrationSettings defines it: a
 * transform from the CT's frame to the room, about the centre of the CT's grid. */
itk::Euler3DTransform<double>::Pointer
MakePoseTransform(const itk::ImageBase<3> * volume, const std::array<double, 6> & pose);

/** Registers the CT volume (HU) to the X-rays. */
template <typename TVolume>
RegistrationResult
RegisterToXRays(const TVolume * volume, const std::vector<XRay> & xrays, const RegistrationSettings & settings);

/** The normalized cross-correlation of a and b over the pixels where mask is 1 (0 if either is constant there). */
double
MaskedNormalizedCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask);

/** The gradient correlation of a and b (columns wide): the mean of the NCCs of their differences along the columns and
 * along the rows, over the pixels whose two neighbours (on that axis) are in the mask. */
double
MaskedGradientCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask, size_t columns);

/** The names RegistrationSettings::Metric takes. */
const std::vector<std::string> &
RegistrationMetricNames();
} // namespace pbdrr

#endif
