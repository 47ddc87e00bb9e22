"""The C++ include graph keeps the layering of docs/design.md: no header include cycle, and the
libraries below the estimator (io, sim, frontend) never include vio_core's headers (issue #50's
acceptance, held here so that a later change cannot undo it silently)."""

import functools
import pathlib
import re

REPO = pathlib.Path(__file__).resolve().parents[2]
SKIP = {"build", "build-fuzz", "build-py", ".venv", ".git", "demo_out"}
INCLUDE = re.compile(r'^\s*#\s*include\s+[<"]([^>"]+)[>"]', re.M)


def sources():
    for path in REPO.rglob("*"):
        if path.suffix in (".h", ".hpp", ".cpp") and not SKIP & set(path.relative_to(REPO).parts):
            yield path


def include_roots(files):
    """Directories an include path is resolved against: every `include/` folder."""
    roots = set()
    for path in files:
        parts = path.relative_to(REPO).parts
        if "include" in parts:
            roots.add(REPO.joinpath(*parts[: parts.index("include") + 1]))
    return sorted(roots)


def resolve(name, including, roots):
    for base in [including.parent, *roots]:
        candidate = base / name
        if candidate.is_file():
            return candidate.resolve()
    return None  # a system or third-party header


@functools.lru_cache(maxsize=1)
def graph():
    """Each source file -> the repository files it includes (read once for all the tests)."""
    files = list(sources())
    roots = include_roots(files)
    edges = {}
    for path in files:
        targets = [resolve(n, path, roots) for n in INCLUDE.findall(path.read_text(errors="replace"))]
        edges[path.resolve()] = [t for t in targets if t is not None]
    return edges


def find_cycle(edges):
    """One include cycle as a list of files, or None (depth-first search with colours)."""
    colour, stack = {}, []

    def visit(node):
        colour[node] = 1
        stack.append(node)
        for nxt in edges.get(node, []):
            if colour.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if colour.get(nxt) is None:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        colour[node] = 2
        return None

    for node in edges:
        if colour.get(node) is None:
            found = visit(node)
            if found:
                return found
    return None


def test_no_include_cycle():
    cycle = find_cycle(graph())
    assert cycle is None, "include cycle: " + " -> ".join(str(p.relative_to(REPO)) for p in cycle)


def test_cycle_finder_finds_one():
    a, b, c = (pathlib.Path(f"/x/{n}.h") for n in "abc")
    assert find_cycle({a: [b], b: [c], c: [a]}) == [a, b, c, a]
    assert find_cycle({a: [b, c], b: [c], c: []}) is None


def test_libraries_below_the_estimator_do_not_include_it():
    vio_core = (REPO / "vio_core").resolve()
    offenders = []
    for path, targets in graph().items():
        top = path.relative_to(REPO.resolve()).parts[0]
        if top in ("io", "sim", "frontend", "types", "geometry"):
            offenders += [f"{path.relative_to(REPO.resolve())} includes {t.relative_to(REPO.resolve())}"
                          for t in targets if vio_core in t.parents]
    assert not offenders, "\n".join(offenders)


def test_libraries_below_the_estimator_do_not_link_it():
    offenders = [str(p.relative_to(REPO)) for top in ("io", "sim", "frontend", "types", "geometry")
                 for p in (REPO / top).rglob("CMakeLists.txt") if re.search(r"\bvio_core\b", p.read_text())]
    assert not offenders, "CMakeLists naming vio_core: " + ", ".join(offenders)
