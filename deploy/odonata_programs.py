"""Where odonata's programs are, for the scripts that start them (odonata-run,
make-identifier-config): beside the script when installed (cmake --install or the package put
them all in bin/), else in a build tree, at services/<name without "odonata-">/<name>."""
import os

# The project's version (CMakeLists.txt project(); tests/cli checks that they agree).
VERSION = "0.1.0"


def installed(script):
    """True when `script` runs from an installation: the programs sit beside it."""
    return os.access(os.path.join(os.path.dirname(os.path.abspath(script)), "odonata-plant"), os.X_OK)


def program(script, build, name):
    """The program `name` (e.g. odonata-fit) for `script`: from the build tree `build` when one is
    given, else the installed one, else the source tree's build/."""
    here = os.path.dirname(os.path.abspath(script))
    if build is None and installed(script):
        return os.path.join(here, name)
    build = build or os.path.join(os.path.dirname(here), "build")
    return os.path.join(build, "services", name.removeprefix("odonata-"), name)


def add_version(parser, name):
    """--version, as odonata's compiled programs print it."""
    parser.add_argument("--version", action="version", version=f"{name} (odonata) {VERSION}")
