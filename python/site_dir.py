"""Prints the directory, relative to the install prefix given as argument, where a Python
module installed under that prefix is found by this Python (used by python/CMakeLists.txt)."""
import os
import sys
import sysconfig

prefix = os.path.abspath(sys.argv[1])


def under_prefix(path):
    relative = os.path.relpath(path, prefix)
    return relative if relative.startswith("lib") else None


# This Python's own default (Debian: /usr/local/lib/python3.X/dist-packages), then any site
# directory on its path under the prefix (Debian's /usr/lib/python3/dist-packages), then the
# standard layout.
candidates = [sysconfig.get_path("platlib")]
candidates += [p for p in sys.path if p.endswith(("site-packages", "dist-packages"))]
for path in candidates:
    relative = under_prefix(path)
    if relative:
        print(relative)
        break
else:
    print(under_prefix(sysconfig.get_path("platlib", "posix_prefix", {"base": prefix, "platbase": prefix})))
