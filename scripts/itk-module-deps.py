#!/usr/bin/python3
"""Which ITK module each ITK header the module includes belongs to, checked against itk-module.cmake (issue 31).

    /usr/bin/python3 scripts/itk-module-deps.py ITK_SOURCE [ITK_BUILD] [--list]

ITK_SOURCE is an ITK source folder (e.g. /work/itk/src-6.0): a header belongs to the module whose folder
Modules/<group>/<module folder>/include holds it (the module's name is the one its itk-module.cmake gives to
itk_module()). ITK_BUILD (optional) is a build of it, for the headers ITK generates (itkConfigure.h,
ITKCommonExport.h, ...): Modules/<group>/<module folder>/ of the build. Only the module's own headers are looked
up: `#include "..."` and `#include <...>` lines whose file is neither in the module (include/, src/, test/) nor a
system header, and is found in ITK.

What is checked, as ITK's module macros use the lists of itk-module.cmake:
- include/ and src/ (the library and its installed templates) against DEPENDS, PRIVATE_DEPENDS and COMPILE_DEPENDS;
- test/ (the GoogleTest sources of PointBasedDRR_TEST_SRCS in test/CMakeLists.txt, which the in-ITK test driver
  builds, and the headers they include) against those and TEST_DEPENDS.
A module used but not listed is an error (exit status 1), even when a listed module depends on it: ITK asks for the
modules used directly. A listed module that nothing includes is reported, not an error (a module can be needed for
what it links or for its factories). --list prints every header with its module.
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)
MODULE_RE = re.compile(r"itk_module\(\s*([A-Za-z0-9_]+)")
# Headers of third-party libraries that ITK provides as a module but keeps outside include/ (or takes from the system).
THIRD_PARTY = {"gtest/": "ITKGoogleTest", "gmock/": "ITKGoogleTest"}


def itk_headers(source, build):
    """{header file name: ITK module name} from the include/ folders of ITK's modules (and their build folders)."""
    headers = {}
    modules_dir = os.path.join(source, "Modules")
    for group in sorted(os.listdir(modules_dir)):
        group_dir = os.path.join(modules_dir, group)
        if not os.path.isdir(group_dir):
            continue
        for folder in sorted(os.listdir(group_dir)):
            module_file = os.path.join(group_dir, folder, "itk-module.cmake")
            if not os.path.isfile(module_file):
                continue
            with open(module_file, encoding="utf-8", errors="replace") as f:
                match = MODULE_RE.search(f.read())
            if not match:
                continue
            name = match.group(1)
            places = [os.path.join(group_dir, folder, "include")]
            if build:
                places.append(os.path.join(build, "Modules", group, folder))
            for place in places:
                if not os.path.isdir(place):
                    continue
                for entry in os.listdir(place):
                    if entry.endswith((".h", ".hxx", ".hpp")):
                        headers.setdefault(entry, name)
    return headers


# itk_module()'s keywords (ITK's ITKModuleMacros.cmake): a module's name may be all capitals too (ITKIOXML).
KEYWORDS = {"DEPENDS", "PRIVATE_DEPENDS", "COMPILE_DEPENDS", "TEST_DEPENDS", "DESCRIPTION", "EXCLUDE_FROM_DEFAULT",
            "ENABLE_SHARED", "FACTORY_NAMES", "TEST_OUTPUT_DIR"}


def declared_modules():
    """The lists of itk-module.cmake's itk_module() call: {keyword: [modules]}."""
    with open(os.path.join(ROOT, "itk-module.cmake"), encoding="utf-8") as f:
        text = f.read()
    call = re.search(r"^itk_module\(([^)]*)\)", text, re.M).group(1)
    lists = {}
    keyword = None
    for word in call.split()[1:]:
        if word in KEYWORDS:
            keyword = word
            lists.setdefault(keyword, [])
        elif keyword and word.startswith("ITK"):
            lists[keyword].append(word)
    return lists


def test_driver_sources():
    """The GoogleTest sources of the in-ITK test driver: PointBasedDRR_TEST_SRCS of test/CMakeLists.txt."""
    with open(os.path.join(ROOT, "test", "CMakeLists.txt"), encoding="utf-8") as f:
        text = f.read()
    names = re.search(r"set\(PointBasedDRR_TEST_SRCS([^)]*)\)", text).group(1).split()
    return [os.path.join(ROOT, "test", name) for name in names]


def includes_of(folders, pattern, sources=()):
    """{included file name: [module files that include it]} for the files of folders whose name matches pattern
    (or the given files), and the module's own headers those include, recursively."""
    own = {}
    for folder in ("include", "src", "test"):
        for dirpath, _, files in os.walk(os.path.join(ROOT, folder)):
            for name in files:
                own.setdefault(name, os.path.join(dirpath, name))
    todo = list(sources)
    for folder in folders:
        for dirpath, _, files in os.walk(os.path.join(ROOT, folder)):
            for name in sorted(files):
                if re.search(pattern, name):
                    todo.append(os.path.join(dirpath, name))
    seen = set()
    used = {}
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        for included in INCLUDE_RE.findall(text):
            base = os.path.basename(included)
            if base in own:
                todo.append(own[base])
            else:
                used.setdefault(included, []).append(os.path.relpath(path, ROOT))
    return used


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    if not args or len(args) > 2:
        sys.stderr.write(__doc__)
        return 2
    source = args[0]
    build = args[1] if len(args) > 1 else None
    if not os.path.isdir(os.path.join(source, "Modules", "Core", "Common")):
        sys.stderr.write(f"itk-module-deps.py: {source} is not an ITK source folder\n")
        return 2
    headers = itk_headers(source, build)
    lists = declared_modules()
    library_listed = set(lists.get("DEPENDS", []) + lists.get("PRIVATE_DEPENDS", []) + lists.get("COMPILE_DEPENDS", []))
    test_listed = library_listed | set(lists.get("TEST_DEPENDS", []))
    status = 0
    for what, folders, pattern, listed in (
        ("include/ and src/", ("include", "src"), r"\.(h|hxx|cxx)$", library_listed),
        ("test/ (the in-ITK driver's sources, PointBasedDRR_TEST_SRCS)", (), None, test_listed),
    ):
        used = includes_of(folders, pattern, () if folders else test_driver_sources())
        by_module = {}
        for header in sorted(used):
            module = headers.get(os.path.basename(header))
            for prefix, name in THIRD_PARTY.items():
                if header.startswith(prefix):
                    module = name
            if module:
                by_module.setdefault(module, []).append(header)
        print(f"{what}: {sum(len(v) for v in by_module.values())} ITK headers from {len(by_module)} modules")
        for module in sorted(by_module):
            mark = "listed" if module in listed else "NOT LISTED"
            print(f"  {module:28} {mark:10} {len(by_module[module])} headers")
            if "--list" in argv or module not in listed:
                for header in by_module[module]:
                    print(f"      {header}  ({', '.join(sorted(set(used[header]))[:3])})")
            if module not in listed:
                status = 1
        unused = sorted(listed - set(by_module))
        if unused:
            print(f"  listed, no header included: {', '.join(unused)}")
    print("itk-module.cmake lists " + "; ".join(f"{k} {' '.join(v)}" for k, v in lists.items() if v))
    print("OK: every ITK module included is listed" if status == 0 else "FAIL: modules included but not listed")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
