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
#ifndef pbdrrDicomLocalizerGeometry_h
#define pbdrrDicomLocalizerGeometry_h

#include "itkDRRProjectionGeometry.h"

#include <string>

namespace pbdrr
{
/** The view of a CT localizer (scout, surview, topogram) as its DICOM header gives it: pbdrr --geometry-from.
 *
 * The header places the image in the patient (room, LPS) frame as a plane: Image Position (0020,0032) is the centre of
 * pixel (0, 0), Image Orientation (0020,0037) the directions of increasing column (r) and row (c) index, Pixel Spacing
 * (0028,0030) the row and column pitch. That plane is the isocenter plane: scanners scale the fan's pixel pitch to the
 * isocenter (so that the image measures the patient where the rotation axis crosses it), and the rows are the table's
 * steps. Distance Source to Patient (0018,1111) is the SAD, Distance Source to Detector (0018,1110) the SID.
 *
 * The view: a localizer beam (a fan across the table along the columns, parallel along the rows), isocenter the centre
 * of the image in that plane, n = c x r (the source on the side from which the image, rows down and columns right, is
 * seen), vup = -c, detector spacing (du, dv) = (column pitch * SID / SAD, row pitch) on the detector plane, no offset.
 * A point of the image plane then projects onto the pixel the header puts it at.
 *
 * Throws std::runtime_error naming the file and the missing or unusable value: not DICOM, not a localizer (Image Type
 * (0008,0008) without LOCALIZER), a header without the distances, a table axis (patient z) that is not along the rows,
 * SID <= SAD. */
struct LocalizerView
{
  /** The view, ready for a DRR filter. */
  itk::DRRProjectionGeometry::Pointer Geometry;
  /** One line for the notes: size, distances, where the source is. */
  std::string Description;
};

/** Reads the view of the localizer in file path (its header only). */
LocalizerView
ReadLocalizerView(const std::string & path);
} // namespace pbdrr

#endif
