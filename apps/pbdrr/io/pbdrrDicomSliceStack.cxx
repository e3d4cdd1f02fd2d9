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
#include "pbdrrDicomSliceStack.h"
#include "pbdrrLoaderText.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pbdrr
{
namespace
{
Vector3
Cross(const Vector3 & a, const Vector3 & b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

double
Dot(const Vector3 & a, const Vector3 & b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/** Every slice has the orientation and size of the first. */
void
CheckOneOrientationAndSize(const std::vector<Slice> & slices, const std::string & what)
{
  const Slice & first = slices.front();
  for (const Slice & slice : slices)
  {
    for (size_t i = 0; i < 6; ++i)
    {
      if (std::abs(slice.Orientation[i] - first.Orientation[i]) > 1e-4)
      {
        Fail("the slices of " + what + " have different orientations (" + slice.Name + "): not one volume");
      }
    }
    if (slice.Size != first.Size)
    {
      Fail("the slices of " + what + " have different sizes (" + slice.Name + "): not one volume");
    }
  }
}

/** The steps along the normal between the slices taken in `order` (increasing `depth`): each one a step forward,
 * without a sideways shift, or with allowShear the same shift per mm at every step (returned in shear). */
std::vector<double>
StepsAlongNormal(const std::vector<Slice> &  slices,
                 const std::vector<size_t> & order,
                 const std::vector<double> & depth,
                 const Vector3 &             normal,
                 const std::string &         what,
                 bool                        allowShear,
                 Vector3 &                   shear)
{
  std::vector<double> gaps;
  for (size_t i = 1; i < order.size(); ++i)
  {
    const Vector3 & a = slices[order[i - 1]].Position;
    const Vector3 & b = slices[order[i]].Position;
    const Vector3   step{ b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double    along = Dot(step, normal);
    if (along < 1e-3)
    {
      Fail("two slices of " + what + " lie at the same position (" + Millimetres(depth[order[i]]) +
           " along the slice normal): duplicated or mixed series");
    }
    const Vector3 sideways{ step[0] - along * normal[0], step[1] - along * normal[1], step[2] - along * normal[2] };
    const double  across = std::sqrt(Dot(sideways, sideways));
    if (!allowShear && across > 1e-3 * along + 0.01)
    {
      Fail("the slice positions of " + what +
           " are not along the slice normal (gantry tilt or sheared series: each slice is shifted " +
           Millimetres(across) + " sideways per " + Millimetres(along) +
           " step); pbdrr renders tilted series of slices, not of frames: resample to an orthogonal grid first");
    }
    if (i == 1)
    {
      shear = { sideways[0] / along, sideways[1] / along, sideways[2] / along };
    }
    const Vector3 expected{ shear[0] * along, shear[1] * along, shear[2] * along };
    const Vector3 off{ sideways[0] - expected[0], sideways[1] - expected[1], sideways[2] - expected[2] };
    if (allowShear && std::sqrt(Dot(off, off)) > 1e-3 * along + 0.01)
    {
      Fail("the sideways shift of the slices of " + what + " changes between slices " + std::to_string(i) + " and " +
           std::to_string(i + 1) + " (" + Millimetres(across) + " per " + Millimetres(along) +
           " step, not the tilt of the first step): not one tilted grid; pbdrr does not render it rather than render "
           "it wrong");
    }
    gaps.push_back(along);
  }
  if (!allowShear)
  {
    shear = { 0.0, 0.0, 0.0 };
  }
  return gaps;
}

/** Every step is `spacing`; a step of a whole multiple of it is reported as missing slices. */
void
CheckEvenSpacing(const std::vector<double> & gaps,
                 const std::vector<size_t> & order,
                 const std::vector<double> & depth,
                 double                      spacing,
                 const std::string &         what)
{
  for (size_t i = 0; i < gaps.size(); ++i)
  {
    if (std::abs(gaps[i] - spacing) > 0.01 * spacing + 1e-3)
    {
      const double       ratio = gaps[i] / spacing;
      const bool         missing = ratio > 1.5 && std::abs(ratio - std::round(ratio)) < 0.05;
      std::ostringstream message;
      message << (missing ? "missing slice(s)" : "uneven slice spacing") << " in " << what << ": slices " << i
              << " and " << i + 1 << " (at " << Millimetres(depth[order[i]]) << " and "
              << Millimetres(depth[order[i + 1]]) << " along the normal) are " << Millimetres(gaps[i])
              << " apart, the spacing is " << Millimetres(spacing);
      if (missing)
      {
        message << " (" << std::lround(ratio) - 1 << " slice(s) missing)";
      }
      message << "; pbdrr does not render it rather than render it wrong";
      Fail(message.str());
    }
  }
}
} // namespace

SliceStack
CheckSliceStack(const std::vector<Slice> & slices, const std::string & what, bool allowShear)
{
  SliceStack stack;
  if (slices.size() < 2)
  {
    return stack;
  }
  CheckOneOrientationAndSize(slices, what);
  const Slice & first = slices.front();
  const Vector3 rowDirection{ first.Orientation[0], first.Orientation[1], first.Orientation[2] };
  const Vector3 columnDirection{ first.Orientation[3], first.Orientation[4], first.Orientation[5] };
  const Vector3 normal = Cross(rowDirection, columnDirection);
  stack.Normal = normal;
  std::vector<double> depth(slices.size());
  for (size_t i = 0; i < slices.size(); ++i)
  {
    depth[i] = Dot(slices[i].Position, normal);
  }
  std::vector<size_t> order(slices.size());
  for (size_t i = 0; i < order.size(); ++i)
  {
    order[i] = i;
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return depth[a] < depth[b]; });
  const std::vector<double> gaps =
    StepsAlongNormal(slices, order, depth, normal, what, allowShear, stack.ShearPerMillimetre);
  std::vector<double> sorted = gaps;
  std::sort(sorted.begin(), sorted.end());
  stack.Spacing = sorted[sorted.size() / 2];
  CheckEvenSpacing(gaps, order, depth, stack.Spacing, what);
  bool increasing = true;
  bool decreasing = true;
  for (size_t i = 0; i < order.size(); ++i)
  {
    increasing = increasing && order[i] == i;
    decreasing = decreasing && order[i] == order.size() - 1 - i;
  }
  stack.Increasing = increasing;
  stack.Ordered = increasing || decreasing;
  return stack;
}

double
SliceStack::StepLength() const
{
  return Spacing * std::sqrt(1.0 + Dot(ShearPerMillimetre, ShearPerMillimetre));
}
} // namespace pbdrr
