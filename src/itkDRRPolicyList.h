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
#ifndef itkDRRPolicyList_h
#define itkDRRPolicyList_h

#include "itkMacro.h"

#include <string>
#include <type_traits>
#include <vector>

namespace itk
{
/** \class DRRPolicyList
 * \brief A registry of compile-time policies of one kind (reconstruction kernels, splats, beams): the single list from
 * which the renderer's dispatch, the enumerators' printed names, the lookup by name and the tests' lists are all
 * derived (itkDRRPolicies.h holds the registrations). What a program says about a policy (pbdrr's help) is the
 * program's, attached to the registered name.
 *
 * Each policy is a small struct that says who it is:
 * \code
 *   static constexpr PointBasedDRREnums::ReconstructionKernel Id = PointBasedDRREnums::ReconstructionKernel::Box;
 *   static constexpr const char * Name = "box"; // its name, lower case, words joined by dashes
 * \endcode
 * The enumerator's printed name is the CamelCase of Name (`box` prints `Box`, `projection-matrix` would print
 * `ProjectionMatrix`), so a policy's name and its enumerator cannot drift apart unnoticed (a test checks both).
 *
 * \tparam TEnum the enumeration the policies are selected by, e.g. PointBasedDRREnums::Splat.
 * \tparam TPolicies the policies, in the order GetEntries() lists them (the first is the default).
 *
 * \sa DRRSamplerFactory, the run-time registry of samplers.
 * \ingroup PointBasedDRR
 */
template <typename TEnum, typename... TPolicies>
class DRRPolicyList
{
public:
  /** The enumeration the policies are selected by. */
  using EnumType = TEnum;

  static_assert(sizeof...(TPolicies) > 0, "a policy list needs at least one policy");
  static_assert((std::is_same<std::remove_cv_t<decltype(TPolicies::Id)>, TEnum>::value && ...),
                "every policy's Id must be of the list's enumeration");

  /** A registered policy: its enumerator and its name. */
  struct Entry
  {
    TEnum       Id;   ///< the enumerator that selects it
    std::string Name; ///< its registered name, e.g. `bilinear`
  };

  /** Every registered policy, in registration order (the first is the default). */
  static std::vector<Entry>
  GetEntries()
  {
    return { Entry{ TPolicies::Id, TPolicies::Name }... };
  }

  /** Number of registered policies. */
  static constexpr unsigned int
  GetNumberOfPolicies()
  {
    return static_cast<unsigned int>(sizeof...(TPolicies));
  }

  /** Calls visit with a value of the policy type whose Id is id and returns what it returns; throws ExceptionObject
   * for an enumerator no policy registers (a value cast from a number). */
  template <typename TVisit>
  static decltype(auto)
  Visit(TEnum id, TVisit && visit)
  {
    return VisitFrom<TVisit, TPolicies...>(id, visit);
  }

  /** The registered name of id (`box`); throws for an unregistered enumerator. */
  static std::string
  GetName(TEnum id)
  {
    return Visit(id, [](auto policy) { return std::string(decltype(policy)::Name); });
  }

  /** The enumerator's own spelling (`Box`), the CamelCase of its name; `INVALID` for an unregistered value. */
  static std::string
  GetEnumeratorName(TEnum id)
  {
    for (const Entry & entry : GetEntries())
    {
      if (entry.Id == id)
      {
        return ToCamelCase(entry.Name);
      }
    }
    return "INVALID";
  }

  /** True and id set if name is a registered name (exact spelling). */
  static bool
  FindByName(const std::string & name, TEnum & id)
  {
    for (const Entry & entry : GetEntries())
    {
      if (entry.Name == name)
      {
        id = entry.Id;
        return true;
      }
    }
    return false;
  }

  /** The registered names, in order. */
  static std::vector<std::string>
  GetNames()
  {
    std::vector<std::string> names;
    for (const Entry & entry : GetEntries())
    {
      names.push_back(entry.Name);
    }
    return names;
  }

  /** `level-alias` -> `LevelAlias`: capitals at the start and after each dash, dashes dropped. */
  static std::string
  ToCamelCase(const std::string & name)
  {
    std::string camel;
    bool        capital = true;
    for (const char c : name)
    {
      if (c == '-')
      {
        capital = true;
        continue;
      }
      camel += capital && c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
      capital = false;
    }
    return camel;
  }

private:
  template <typename TVisit, typename TFirst, typename... TRest>
  static decltype(auto)
  VisitFrom(TEnum id, TVisit & visit)
  {
    if (id == TFirst::Id)
    {
      return visit(TFirst{});
    }
    if constexpr (sizeof...(TRest) > 0)
    {
      return VisitFrom<TVisit, TRest...>(id, visit);
    }
    else
    {
      itkGenericExceptionMacro("no registered policy for enumerator " << static_cast<int>(id));
    }
  }
};
} // namespace itk

#endif
