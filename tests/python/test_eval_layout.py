"""vid_eval's layout (eval/README.md "Layout", issue #50): the metrics' math in vid_eval.core
does no file I/O and no plotting, and depends on nothing above it."""
import ast
import pathlib

CORE = pathlib.Path(__file__).resolve().parents[2] / "eval" / "vid_eval" / "core"
IO_CALLS = {"open", "read_text", "write_text", "read_bytes", "write_bytes", "loadtxt", "savetxt", "genfromtxt",
            "dump", "load", "savefig", "mkdir"}


def _modules():
    return sorted(p for p in CORE.glob("*.py") if p.name != "__init__.py")


def test_core_has_the_metrics():
    names = {p.stem for p in _modules()}
    assert {"alignment", "ate", "rpe", "force_metrics", "mass_metrics", "series"} <= names


def test_core_does_no_io_and_no_plotting_and_imports_nothing_above_it():
    for path in _modules():
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
                for n in names:
                    assert not n.startswith(("matplotlib", "json", "csv", "pathlib")), f"{path.name} imports {n}"
                if isinstance(node, ast.ImportFrom) and node.level >= 2:
                    assert node.module == "errors", f"{path.name}: from {'.' * node.level}{node.module} (above core)"
                if isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").startswith("vid_eval"):
                    assert node.module.startswith("vid_eval.core"), f"{path.name} imports {node.module}"
            if isinstance(node, ast.Call):
                f = node.func
                name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else ""
                assert name not in IO_CALLS, f"{path.name}:{node.lineno}: {name}() is file I/O"
