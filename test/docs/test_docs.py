#!/usr/bin/python3
"""The documentation against the code and the repository:
 - docs/nodelets.md is what scripts/nodelet_docs writes from cfg/<Nodelet>.cfg and
   cfg/<Nodelet>.params.yaml;
 - every parameter a nodelet reads (param(...), getParam(...), param<T>(...), its reconfigure
   config, the libraries that read its private namespace) is documented in exactly one of the
   two, every documented one is read, and literal defaults agree with the code;
 - every relative link of README.md and docs/*.md resolves inside the repository (anchors too);
 - nothing in the repository points at the design brief that lives outside it.
Run directly, or with --gtest_output=xml:FILE (as scripts/test runs the gtests) for a JUnit file."""
import importlib.machinery
import importlib.util
import os
import pathlib
import re
import sys
import time
import unittest
import xml.etree.ElementTree as ET

REPO = pathlib.Path(__file__).resolve().parents[2]


def load_generator():
    loader = importlib.machinery.SourceFileLoader("nodelet_docs", str(REPO / "scripts" / "nodelet_docs"))
    spec = importlib.util.spec_from_loader("nodelet_docs", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


GENERATOR = load_generator()


# ------------------------------------------------------------------ reading C++

def strip_comments(code):
    """The code without // and /* */ comments; string and character literals kept."""
    out, i, n = [], 0, len(code)
    while i < n:
        c = code[i]
        if c in "\"'":
            j = i + 1
            while j < n and code[j] != c:
                j += 2 if code[j] == "\\" else 1
            out.append(code[i:j + 1])
            i = j + 1
        elif code.startswith("//", i):
            i = code.find("\n", i)
            i = n if i < 0 else i
        elif code.startswith("/*", i):
            i = code.find("*/", i + 2)
            i = n if i < 0 else i + 2
        else:
            out.append(c)
            i += 1
    return "".join(out)


def arguments(code, open_paren):
    """The top-level arguments of the call whose '(' is at open_paren."""
    args, depth, start, i = [], 0, open_paren + 1, open_paren
    while i < len(code):
        c = code[i]
        if c in "\"'":
            j = i + 1
            while code[j] != c:
                j += 2 if code[j] == "\\" else 1
            i = j
        elif c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
            if depth == 0:
                args.append(code[start:i].strip())
                return args
        elif c == "," and depth == 1:
            args.append(code[start:i].strip())
            start = i + 1
        i += 1
    raise ValueError("unbalanced call at %d" % open_paren)


STRING = re.compile(r'^"((?:[^"\\]|\\.)*)"$')


def literal(expression):
    """(value, type) of a C++ literal default, or None for anything else."""
    e = expression.strip()
    m = STRING.match(e) or re.match(r'^std::string\(\s*"((?:[^"\\]|\\.)*)"\s*\)$', e)
    if m:
        return m.group(1), "string"
    if re.match(r"^std::string\(\s*\)$", e):
        return "", "string"
    if e in ("true", "false"):
        return e == "true", "bool"
    if re.match(r"^-?\d+$", e):
        return int(e), "int"
    if re.match(r"^-?(\d+\.\d*|\.\d+|\d+)([eE][-+]?\d+)?$", e):
        return float(e), "double"
    return None


TEMPLATE_TYPES = {"std::string": "string", "int": "int", "double": "double", "bool": "bool"}
PARAM_CALL = re.compile(r"\b(getParam|param)\s*(?:<\s*([\w:]+)\s*>)?\s*\(")


def parameter_reads(code):
    """Every param()/getParam() call: dict(name or None, first, default, template)."""
    reads = []
    for m in PARAM_CALL.finditer(code):
        args = arguments(code, m.end() - 1)
        name = STRING.match(args[0])
        reads.append({"name": name.group(1) if name else None, "first": args[0],
                      "default": args[2] if m.group(1) == "param" and len(args) > 2 else None,
                      "template": m.group(2)})
    return reads


def loop_range(code, variable):
    """The range expression of the range-for loop that declares `variable`."""
    m = re.search(r"for\s*\([^;()]*?\b%s\s*:\s*([^()]*(?:\(\))?)\s*\)" % re.escape(variable), code)
    return m.group(1).strip() if m else None


def string_array(code, array):
    """The string literals of `array[] = {...}`, or None."""
    m = re.search(r"\b%s\s*\[\s*\]\s*=\s*\{([^}]*)\}" % re.escape(array), code)
    return re.findall(r'"((?:[^"\\]|\\.)*)"', m.group(1)) if m else None


def source_settings(source):
    """{setting: default expression or None} a frame source reads (src/sources/<source>_source.cpp)."""
    path = REPO / "src" / "sources" / (source + "_source.cpp")
    code = strip_comments(path.read_text())
    found = {}
    for m in re.finditer(r"\bsettings\.(?:text|flag|number)\s*\(", code):
        args = arguments(code, m.end() - 1)
        name = STRING.match(args[0])
        if name:
            found[name.group(1)] = args[1] if len(args) > 1 else None
    return found


# ------------------------------------------------------------------ the tests

class NodeletDocumentation(unittest.TestCase):
    def test_page_is_what_the_generator_writes(self):
        page = GENERATOR.PAGE.read_text() if GENERATOR.PAGE.exists() else ""
        self.assertTrue(page == GENERATOR.render(),
                        "docs/nodelets.md is stale: run scripts/nodelet_docs and commit the result")

    def test_every_parameter_read_is_documented_once_and_every_documented_one_is_read(self):
        for name in GENERATOR.NODELETS:
            with self.subTest(nodelet=name):
                self.check_nodelet(GENERATOR.load_nodelet(name))

    def check_nodelet(self, spec):
        files = "cfg/%s.cfg nor cfg/%s.params.yaml" % (spec["name"], spec["name"])
        code = strip_comments((REPO / spec["source"]).read_text())
        static = {p["name"]: p for p in spec.get("parameters", [])}
        settings = {s["name"]: s for s in spec.get("settings", [])}
        dynamic = {p["name"]: p for p in spec["reconfigurable"]}
        indirect = {i["code"]: i["parameters"] for i in spec.get("indirect", [])}

        twice = (set(static) & set(settings)) | ((set(static) | set(settings)) & set(dynamic))
        self.assertFalse(twice, "%s: documented in both cfg/%s.cfg and cfg/%s.params.yaml"
                         % (sorted(twice), spec["name"], spec["name"]))
        documented = set(static) | set(settings) | set(dynamic)

        read = set()
        for call in parameter_reads(code):
            if call["name"] is not None:
                names = [call["name"]]
            else:
                where = loop_range(code, call["first"])
                names = string_array(code, where) if where else None
                if names is None:
                    names = indirect.get(where)
                self.assertIsNotNone(names, "%s: cannot tell which parameters `%s` reads (range `%s`); "
                                     "declare it under `indirect` in cfg/%s.params.yaml"
                                     % (spec["source"], call["first"], where, spec["name"]))
            for n in names:
                self.assertTrue(n in documented, "%s reads ~%s, which neither %s documents" % (spec["source"], n, files))
                read.add(n)
            if call["name"] in static:
                self.check_default(spec, static[call["name"]], call)

        if spec["has_cfg"]:
            self.assertTrue("dynamic_reconfigure::Server<%sConfig>" % spec["name"] in code,
                            "%s has no reconfigure server for cfg/%s.cfg" % (spec["source"], spec["name"]))
        for n in dynamic:
            self.assertTrue(re.search(r"\b(?:config|c)\.%s\b" % n, code),
                            "cfg/%s.cfg documents %s, which %s never uses" % (spec["name"], n, spec["source"]))
        for n, p in static.items():
            if p.get("read_by"):
                self.assertTrue(p["code"] in code, "~%s is read by %s through `%s`, not in %s"
                              % (n, p["read_by"], p["code"], spec["source"]))
            else:
                self.assertTrue(n in read, "cfg/%s.params.yaml documents ~%s, which %s never reads"
                              % (spec["name"], n, spec["source"]))
        for n in settings:
            self.assertTrue(n in read, "cfg/%s.params.yaml documents the setting ~%s, which %s never reads"
                          % (spec["name"], n, spec["source"]))
        if settings:
            self.check_settings(spec, settings)

    def check_default(self, spec, documented, call):
        value = literal(call["default"]) if call["default"] is not None else None
        if value is None:
            return  # computed defaults (e.g. "camera_" + n) are described, not compared
        code_type = TEMPLATE_TYPES.get(call["template"], value[1])
        where = "~%s in %s" % (documented["name"], spec["source"])
        self.assertEqual(documented["type"], code_type, where + ": type")
        self.assertEqual(documented.get("default"), value[0], where + ": default")
        self.assertEqual(type(documented.get("default")), type(value[0]), where + ": default's type")

    def check_settings(self, spec, settings):
        sources = sorted({s for setting in settings.values() for s in setting["sources"]})
        for source in sources:
            read = source_settings(source)
            for n, default in read.items():
                self.assertTrue(n in settings, "the %s source reads the setting %s, which cfg/%s.params.yaml "
                              "does not document" % (source, n, spec["name"]))
                self.assertTrue(source in settings[n]["sources"], "setting %s: the %s source reads it" % (n, source))
                documented = settings[n].get("default")
                if isinstance(documented, dict):
                    documented = documented[source]
                value = literal(default) if default is not None else None
                if value is not None:
                    self.assertEqual(documented, value[0], "setting %s of the %s source: default" % (n, source))
            for n, setting in settings.items():
                if source in setting["sources"]:
                    self.assertTrue(n in read, "cfg/%s.params.yaml says the %s source reads %s; it does not"
                                  % (spec["name"], source, n))


LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")


def anchors(markdown_file):
    """GitHub's heading anchors of a Markdown file."""
    seen, out = {}, set()
    in_code = False
    for line in markdown_file.read_text().splitlines():
        if line.startswith("```"):
            in_code = not in_code
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m and not in_code:
            slug = re.sub(r"[^\w\- ]", "", m.group(1).lower()).replace(" ", "-")
            count = seen.get(slug, 0)
            seen[slug] = count + 1
            out.add(slug if count == 0 else "%s-%d" % (slug, count))
    return out


def markdown_links(path):
    in_code = False
    for number, line in enumerate(path.read_text().splitlines(), 1):
        if line.startswith("```"):
            in_code = not in_code
            continue
        if not in_code:
            for m in LINK.finditer(re.sub(r"`[^`]*`", "", line)):
                yield number, m.group(1)


def repository_files():
    """Every file of the checkout but git's and the build workspace's."""
    for root, dirs, files in os.walk(REPO):
        dirs[:] = sorted(d for d in dirs if not (pathlib.Path(root) == REPO and d in (".git", ".ws")))
        for name in sorted(files):
            yield pathlib.Path(root) / name


class Links(unittest.TestCase):
    def test_every_link_of_the_readme_and_the_manual_resolves_inside_the_repository(self):
        pages = [REPO / "README.md"] + sorted((REPO / "docs").glob("*.md"))
        for page in pages:
            for number, target in markdown_links(page):
                where = "%s:%d: %s" % (page.relative_to(REPO), number, target)
                with self.subTest(link=where):
                    self.assertNotRegex(target, r"^[a-zA-Z][\w+.-]*:", where + " leaves the repository")
                    path, _, anchor = target.partition("#")
                    resolved = (page.parent / path).resolve() if path else page
                    self.assertTrue(resolved == REPO or REPO in resolved.parents, where + " leaves the repository")
                    self.assertTrue(resolved.exists(), where + " does not exist")
                    if anchor and resolved.suffix == ".md":
                        self.assertTrue(anchor in anchors(resolved), where + ": no such heading")

    def test_nothing_points_at_the_design_brief_outside_the_repository(self):
        needles = ["DESIGN" + ".md", "shared" + "/"]  # split: this file must not match itself
        for path in repository_files():
            relative = path.relative_to(REPO)
            if path.suffix == ".png":
                continue
            try:
                content = path.read_text()
            except UnicodeDecodeError:
                continue
            for needle in needles:
                with self.subTest(file=str(relative), needle=needle):
                    self.assertFalse(needle in content, "%s mentions %s" % (relative, needle))


# ------------------------------------------------------------------ running

class JUnitResult(unittest.TextTestResult):
    """Also keeps every case's outcome (skips included) for a JUnit XML file."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.cases = []
        self.started = time.time()

    def startTest(self, test):
        self.started = time.time()
        super().startTest(test)

    def _record(self, test, kind=None, message=""):
        self.cases.append((test, time.time() - self.started, kind, message))

    def addSuccess(self, test):
        super().addSuccess(test)
        self._record(test)

    def addFailure(self, test, err):
        super().addFailure(test, err)
        self._record(test, "failure", self._exc_info_to_string(err, test))

    def addError(self, test, err):  # also a setUpClass that failed
        super().addError(test, err)
        self._record(test, "error", self._exc_info_to_string(err, test))

    def addSkip(self, test, reason):
        super().addSkip(test, reason)
        self._record(test, "skipped", reason)

    def addSubTest(self, test, subtest, err):
        super().addSubTest(test, subtest, err)
        if err is not None:
            kind = "failure" if issubclass(err[0], test.failureException) else "error"
            self._record(subtest, kind, self._exc_info_to_string(err, test))


def write_junit(result, path, suite_name):
    count = lambda kind: str(sum(k == kind for _, _, k, _ in result.cases))  # noqa: E731
    suite = ET.Element("testsuite", name=suite_name, tests=str(len(result.cases)), failures=count("failure"),
                       errors=count("error"), skipped=count("skipped"))
    for test, seconds, kind, message in result.cases:
        if isinstance(test, unittest.TestCase):
            classname, name = type(test).__name__, test.id().split(".", 2)[-1]
        else:  # a setUpClass that failed: unittest reports it as "setUpClass (module.Class)"
            classname, name = "setUpClass", str(test)
        case = ET.SubElement(suite, "testcase", classname=classname, name=name, time="%.3f" % seconds)
        if kind == "skipped":  # as gtest marks a skipped case
            case.set("status", "run")
            case.set("result", "skipped")
            ET.SubElement(case, "skipped", message=message)
        elif kind:
            ET.SubElement(case, kind, message=message.strip().splitlines()[-1]).text = message
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def main(argv, module=None):
    """Runs the tests of `module` (this one by default); --gtest_output=xml:FILE writes a JUnit
    report, as the gtest executables do (scripts/test reads them all the same way)."""
    xml = next((a.split("=", 1)[1].removeprefix("xml:") for a in argv if a.startswith("--gtest_output=")), None)
    module = module or sys.modules[__name__]
    tests = unittest.defaultTestLoader.loadTestsFromModule(module)
    result = unittest.TextTestRunner(resultclass=JUnitResult, verbosity=2).run(tests)
    if xml:
        pathlib.Path(xml).parent.mkdir(parents=True, exist_ok=True)
        write_junit(result, xml, pathlib.Path(module.__file__).stem)
    return 0 if result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
