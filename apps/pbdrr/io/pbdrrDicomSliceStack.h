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
#ifndef pbdrrDicomSliceStack_h
#define pbdrrDicomSliceStack_h

#include <array>
#include <string>
#include <vector>

namespace pbdrr
{
using Vector3 = std::array<double, 3>;

/** One slice of a DICOM volume: a file of a series, or a frame of a multi-frame file. */
struct Slice
{
  std::string         Name;        // the file, or the file and frame
  Vector3             Position;    // Image Position (Patient), mm
  std::vector<double> Orientation; // Image Orientation (Patient): row and column direction cosines
  std::string         Size;        // rows x columns
};

/** How the slices stack up along their normal. */
struct SliceStack
{
  Vector3 Normal{ { 0.0, 0.0, 1.0 } }; // row direction x column direction of the slices
  double  Spacing{ 1.0 };              // mm between neighbouring slices
  bool    Increasing{ true };          // given in increasing position along the normal
  bool    Ordered{ true };             // given in increasing or decreasing order, not shuffled
  /** The slices' sideways shift per mm along the normal (a gantry tilt: a sheared grid), in increasing depth order;
   * zero for an orthogonal stack. */
  Vector3 ShearPerMillimetre{ { 0.0, 0.0, 0.0 } };
  /** mm from one slice to the next: Spacing, lengthened by the shear. */
  double
  StepLength() const;
};

/** Checks that the slices form one regular 3D grid: one orientation and size, no duplicates, no gaps, even spacing,
 * and positions along the normal, or with allowShear shifted sideways by the same vector at every step (a gantry
 * tilt: a sheared grid, ShearPerMillimetre); throws std::runtime_error with the reason otherwise. `what` names them
 * in messages ("the series", "the frames of F"). Fewer than 2 slices give the default stack. */
SliceStack
CheckSliceStack(const std::vector<Slice> & slices, const std::string & what, bool allowShear = false);
} // namespace pbdrr

#endif
