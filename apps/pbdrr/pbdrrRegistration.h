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

/** What `pbdrr register` asks of the registration, itk::PointBasedDRRRegistrationMethod (its class comment tells the
 * pose, the similarity and the search): the values of the command line, with pbdrr's defaults. */
struct RegistrationSettings
{
  std::array<double, 6> StartPose{}; // tx ty tz (mm) rx ry rz (degrees)
  /** The schedule: one detector shrink factor per level (empty: the method's default), and per level the kept points
   * (empty: Samples on every level) and the smoothing sigma in mm (empty: none). */
  std::vector<unsigned> Shrink;
  std::vector<uint64_t> LevelSamples;
  std::vector<double>   LevelSigmas;
  bool                  Exact{ false }; // the exact Siddon projector instead of kept points
  /** The exact projector's rays per pixel side (PointBasedDRRMetricv4::SetExactRaysPerPixelSide()). */
  unsigned ExactRaysPerSide{ 2 };
  /** The similarity: one of itk::DRRImageSimilarity::GetMetricNames() ("ncc" or "gc"). */
  std::string Metric{ "gc" };
  /** The optimizer: one of itk::PointBasedDRRRegistrationMethod's GetOptimizerNames() (empty: its default). */
  std::string Optimizer;
  uint64_t    Samples{ 0 }; // kept points (0: the metric's default)
  uint64_t    Seed{ 0 };
  unsigned    Starts{ 1 };         // the global stage's starts on the first level
  double      StartRadius{ 10.0 }; // their spread about the start, mm and degrees
  double      MaxSeconds{ 0.0 };   // 0: no limit
  unsigned    Threads{ 0 };
  bool        Verbose{ false }; // each level's similarity and pose on stderr
};

/** The outcome of a registration. */
struct RegistrationResult
{
  std::array<double, 6>                                   Pose{}; // tx ty tz (mm) rx ry rz (degrees)
  double                                                  StartSimilarity{ 0.0 };
  double                                                  Similarity{ 0.0 }; // at full resolution, mean over X-rays
  unsigned                                                Evaluations{ 0 };
  unsigned                                                DerivativeEvaluations{ 0 }; // of those, with a derivative
  double                                                  Seconds{ 0.0 };
  bool                                                    StoppedByTime{ false };
  std::vector<itk::Image<float, 2>::ConstPointer>         FinalDRRs; // at full resolution, one per X-ray
  std::vector<itk::Image<unsigned char, 2>::ConstPointer> Masks;     // the field both cover, per X-ray (1: counted)
};

/** For a view set from a projection matrix: throws std::runtime_error if the volume, moved by up to
 * marginInMillimeters, reaches beyond the detector plane, where the rays end (SID = fx du: a pixel pitch du too small
 * for the matrix's focal length fx puts the detector inside the volume, and the DRR would be cut or empty). Names the
 * pitch that is needed, and the view as flag says. */
void
CheckDetectorBeyondVolume(const itk::DRRProjectionGeometry * geometry,
                          const itk::ImageBase<3> *          volume,
                          double                             marginInMillimeters,
                          const std::string &                flag);

/** The rigid pose tx ty tz (mm) rx ry rz (degrees) of the CT in the room, as itk::PointBasedDRRRegistrationMethod
 * defines it: a transform from the CT's frame to the room, about the centre of the CT's grid. */
itk::Euler3DTransform<double>::Pointer
MakePoseTransform(const itk::ImageBase<3> * volume, const std::array<double, 6> & pose);

/** Registers the CT volume (HU) to the X-rays with itk::PointBasedDRRRegistrationMethod; checks first that each
 * X-ray's detector lies beyond the CT (CheckDetectorBeyondVolume(), naming the X-ray); with settings.Verbose, prints
 * each level's similarity and pose (the method's IterationEvent). */
template <typename TVolume>
RegistrationResult
RegisterToXRays(const TVolume * volume, const std::vector<XRay> & xrays, const RegistrationSettings & settings);
} // namespace pbdrr

#endif
