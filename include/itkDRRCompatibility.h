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
#ifndef itkDRRCompatibility_h
#define itkDRRCompatibility_h

#include "itkMacro.h"

/** \file itkDRRCompatibility.h
 * \brief The differences between the ITK versions the module builds against (Debian's 5.2.1, 5.4, 6.0 with
 * ITK_LEGACY_REMOVE=ON), in one place, so that the rest of the code is written once, in ITK 6's spelling.
 *
 * Included by every header that declares an ITK class of the module. What it maps:
 * - itkOverrideGetNameOfClassMacro(thisClass): ITK 6.0 and 5.4 define it, deprecate itkTypeMacro(thisClass, superclass)
 *   and make it a static_assert under ITK_FUTURE_LEGACY_REMOVE (its message: call itkOverrideGetNameOfClassMacro);
 *   ITK 5.2 has only itkTypeMacro. Defined here, with 5.2's expansion of itkTypeMacro, where ITK does not define it.
 *   (No class of the module is without an ITK base, so itkVirtualGetNameOfClassMacro, for itkTypeMacroNoParent, which
 *   5.2 lacks too, is not needed.)
 * - ProcessObject::VerifyInputInformation() is declared `ITKv5_CONST` on 5.x (`const` unless ITKV4_COMPATIBILITY) and
 *   `const` on 6.0, where ITKv5_CONST is an error under ITK_LEGACY_REMOVE: the module writes `const`, and an ITK built
 *   with ITKV4_COMPATIBILITY (where it is not const) is refused here.
 * - itk::DRRCoordinateTypeOf<TFunction>: the coordinate type of an ImageFunction, `CoordinateType` on 6.0 (and 5.4),
 *   `CoordRepType` on 5.2. (ITK 6 names the template parameter TCoordinate, 5.2 TCoordRep; the module's interpolator
 *   follows ITK 6: the name of a template parameter is no interface.)
 *
 * \ingroup PointBasedDRR
 */

#if defined(ITKV4_COMPATIBILITY)
#error "PointBasedDRR needs an ITK built without ITKV4_COMPATIBILITY (VerifyInputInformation() is const from ITK 5)"
#endif

// itkOverrideGetNameOfClassMacro(thisClass): `const char * GetNameOfClass() const override`, returning the class name:
// ITK's own on 5.4 and 6.0; on 5.2 the expansion of itkTypeMacro(thisClass, superclass). (Documented in the \file
// comment above: Doxygen predefines the macro, as docs/Doxyfile.in does ITK's, so it never reads this definition.)
#ifndef itkOverrideGetNameOfClassMacro
#define itkOverrideGetNameOfClassMacro(thisClass)                                                                      \
  const char * GetNameOfClass() const override                                                                         \
  {                                                                                                                    \
    return #thisClass;                                                                                                 \
  }                                                                                                                    \
  ITK_MACROEND_NOOP_STATEMENT
#endif

namespace itk
{
namespace DRRCompatibilityDetail
{
template <typename TFunction>
auto
CoordinateTypeOf(int) -> typename TFunction::CoordinateType; // ITK 5.4 and 6.0
template <typename TFunction>
auto
CoordinateTypeOf(long) -> typename TFunction::CoordRepType; // ITK 5.2
} // namespace DRRCompatibilityDetail

/** The coordinate type of the ImageFunction TFunction: its CoordinateType on ITK 5.4 and 6.0, its CoordRepType on
 * ITK 5.2 (6.0 deprecates that name and removes it under ITK_FUTURE_LEGACY_REMOVE; 5.4 has both). A substitution
 * failure, not an error, for a type that has neither. */
template <typename TFunction>
using DRRCoordinateTypeOf = decltype(DRRCompatibilityDetail::CoordinateTypeOf<TFunction>(0));
} // namespace itk

#endif
