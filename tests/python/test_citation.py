"""LICENSE and CITATION.cff at the root agree with each other and with the packages' metadata."""
import re
import tomllib

import yaml

from conftest import REPO


def _cff():
    return yaml.safe_load((REPO / "CITATION.cff").read_text())


def test_citation_has_the_required_fields():
    cff = _cff()
    for key in ("cff-version", "message", "title", "authors", "version", "license"):
        assert cff.get(key), key
    assert cff["cff-version"] == "1.2.0"
    assert all("name" in a or "family-names" in a for a in cff["authors"])
    for ref in cff.get("references", []):
        assert ref["title"] and ref["authors"] and ref["year"] > 1900, ref


def test_citation_version_is_the_project_version():
    cmake = (REPO / "CMakeLists.txt").read_text()
    version = re.search(r"project\(vid_msckf VERSION (\S+)", cmake).group(1)
    assert _cff()["version"] == version
    assert tomllib.loads((REPO / "python" / "pyproject.toml").read_text())["project"]["version"] == version


def test_one_licence_everywhere():
    text = (REPO / "LICENSE").read_text()
    assert "Apache License" in text and "Version 2.0, January 2004" in text
    assert _cff()["license"] == "Apache-2.0"
    for pyproject in ("eval/pyproject.toml", "python/pyproject.toml"):
        meta = tomllib.loads((REPO / pyproject).read_text())["project"]
        # PEP 639 SPDX string (eval/, setuptools >= 77) or the older table (python/: kept for
        # scikit-build-core 0.8-0.10); either way the same licence.
        lic = meta["license"]
        assert (lic if isinstance(lic, str) else lic.get("text")) == "Apache-2.0", pyproject
