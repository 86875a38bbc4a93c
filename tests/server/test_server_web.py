"""The web page's side of `wish serve`: the include=mesh,sphere,distortion geometry block (checked against the
map-quality summaries it must agree with), the static files at GET / (content types, no way out of --web-dir or
--three-dir) and the page as served by default: web/src with Debian's three.js under /vendor/three/."""
import json
import math
import os
import posixpath
import re
import shutil
import tempfile
import unittest

import wish_server_harness as h

SKIP = h.skip_reason_binary()
MESHES = os.path.join(h.SOURCE_DIR, "data", "meshes")


def triangle_area(v, a, b, c):
    p = [v[3 * a + k] for k in range(3)]
    q = [v[3 * b + k] for k in range(3)]
    r = [v[3 * c + k] for k in range(3)]
    u = [q[k] - p[k] for k in range(3)]
    w = [r[k] - p[k] for k in range(3)]
    n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    return 0.5 * math.sqrt(sum(x * x for x in n))


@unittest.skipIf(SKIP, SKIP or "")
class GeometryBlockTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-web-")
        cls.models = h.models_dir_with_default(cls.tmp)
        cls.server = h.Server(models_dir=cls.models, args=["--workers", "2"])
        cls.ellipsoid = h.read_bytes(os.path.join(MESHES, "ellipsoid.off"))
        r = cls.server.post_mesh("/v1/describe?lmax=6&include=invariants,quality,coefficients,mesh,sphere,distortion", cls.ellipsoid)
        assert r.status == 200, r.body
        cls.full = r.json()

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_schema_and_counts_match_the_mesh(self):
        h.validate("DescribeResult", self.full)
        g = self.full["geometry"]
        prepared = self.full["mesh"]["prepared"]
        self.assertEqual(g["vertex_count"], prepared["vertices"])
        self.assertEqual(g["face_count"], prepared["faces"])
        self.assertEqual(len(g["vertices"]), 3 * g["vertex_count"])
        self.assertEqual(len(g["sphere"]), 3 * g["vertex_count"])
        self.assertEqual(len(g["faces"]), 3 * g["face_count"])
        self.assertEqual(len(g["conformal_distortion"]), g["face_count"])
        self.assertEqual(len(g["area_ratio"]), g["face_count"])
        self.assertEqual(min(g["faces"]), 0)
        self.assertEqual(max(g["faces"]), g["vertex_count"] - 1)

    def test_sphere_points_are_unit_vectors(self):
        s = self.full["geometry"]["sphere"]
        worst = max(abs(math.sqrt(s[i] ** 2 + s[i + 1] ** 2 + s[i + 2] ** 2) - 1) for i in range(0, len(s), 3))
        self.assertLess(worst, 1e-12)

    def test_vertices_span_the_reported_bounding_box(self):
        v = self.full["geometry"]["vertices"]
        prepared = self.full["mesh"]["prepared"]
        for k in range(3):
            self.assertAlmostEqual(min(v[k::3]), prepared["bbox_min"][k], places=12)
            self.assertAlmostEqual(max(v[k::3]), prepared["bbox_max"][k], places=12)

    def test_distortion_arrays_summarise_to_the_quality_report(self):
        g, q = self.full["geometry"], self.full["map"]["quality"]
        k = g["conformal_distortion"]
        self.assertTrue(all(x is not None and x >= 1 - 1e-12 for x in k))
        self.assertAlmostEqual(sum(k) / len(k), q["conformal_mean"], delta=1e-12 * q["conformal_mean"])
        self.assertEqual(max(k), q["conformal_max"])
        ordered = sorted(k)
        self.assertEqual(ordered[math.ceil(0.99 * len(k)) - 1], q["conformal_p99"])
        ratio = g["area_ratio"]
        area_distortion = math.exp(sum(abs(math.log(r)) for r in ratio) / len(ratio))
        self.assertAlmostEqual(area_distortion, q["area_distortion"], delta=1e-12 * q["area_distortion"])

    def test_area_ratio_is_sphere_share_over_input_share(self):
        g = self.full["geometry"]
        v, s, f = g["vertices"], g["sphere"], g["faces"]
        tri = [(f[i], f[i + 1], f[i + 2]) for i in range(0, len(f), 3)]
        a_in = [triangle_area(v, *t) for t in tri]
        a_sp = [triangle_area(s, *t) for t in tri]
        total_in, total_sp = sum(a_in), sum(a_sp)
        for i in range(0, len(tri), max(1, len(tri) // 50)):
            expected = (a_sp[i] / total_sp) / (a_in[i] / total_in)
            self.assertAlmostEqual(g["area_ratio"][i], expected, delta=1e-9 * expected)
        # the shares sum to one on both sides
        self.assertAlmostEqual(sum(r * a / total_in for r, a in zip(g["area_ratio"], a_in)), 1.0, delta=1e-9)

    def test_response_without_include_is_unchanged(self):
        plain = self.server.post_mesh("/v1/describe?lmax=6", self.ellipsoid).json()
        explicit = self.server.post_mesh("/v1/describe?lmax=6&include=invariants,quality", self.ellipsoid).json()
        self.assertNotIn("geometry", plain)
        self.assertEqual(sorted(plain), sorted(explicit))
        self.assertEqual(sorted(plain), ["descriptor", "map", "mesh", "request_id", "timings"])
        self.assertEqual(plain["descriptor"]["invariants"], self.full["descriptor"]["invariants"])

    def test_each_part_alone(self):
        r = self.server.post_mesh("/v1/describe?lmax=6&include=sphere", self.ellipsoid).json()
        self.assertEqual(sorted(r["geometry"]), ["face_count", "sphere", "vertex_count"])
        self.assertEqual(r["geometry"]["sphere"], self.full["geometry"]["sphere"])  # deterministic map
        r = self.server.post_mesh("/v1/describe?lmax=6&include=distortion", self.ellipsoid).json()
        self.assertEqual(sorted(r["geometry"]), ["area_ratio", "conformal_distortion", "face_count", "vertex_count"])

    def test_classify_with_geometry_in_a_batch(self):
        if self.models is None:
            self.skipTest("no default model")
        r = self.server.post_multipart("/v1/classify", [("mesh", "ellipsoid.off", self.ellipsoid),
                                                         ("mesh", "eight.off", h.read_bytes(os.path.join(MESHES, "eight.off")))],
                                       fields={"include": "mesh"})
        self.assertEqual(r.status, 207, r.body[:400])  # one part mapped, one refused: Multi-Status
        body = r.json()
        h.validate("BatchResponse", body)
        ok, bad = body["results"]
        self.assertEqual(ok["status"], 200)
        self.assertIn("prediction", ok["result"])
        self.assertEqual(sorted(ok["result"]["geometry"]), ["face_count", "faces", "vertex_count", "vertices"])
        self.assertEqual(bad["status"], 422)
        self.assertEqual(bad["error"]["code"], "genus_nonzero")

    def test_unknown_include_item_is_refused(self):
        r = self.server.post_mesh("/v1/describe?include=mesh,spheres", self.ellipsoid)
        self.assertEqual(r.status, 400)
        self.assertEqual(r.json()["error"]["code"], "invalid_parameter")
        self.assertIn("spheres", r.json()["error"]["message"])


@unittest.skipIf(SKIP, SKIP or "")
class StaticFilesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-web-static-")
        cls.web = os.path.join(cls.tmp, "web")
        os.makedirs(os.path.join(cls.web, "vendor"))
        with open(os.path.join(cls.web, "index.html"), "w") as f:
            f.write("<!doctype html><title>page</title>")
        with open(os.path.join(cls.web, "vendor", "lib.js"), "w") as f:
            f.write("export const x = 1;\n")
        with open(os.path.join(cls.web, ".secret"), "w") as f:
            f.write("hidden")
        with open(os.path.join(cls.tmp, "outside.txt"), "w") as f:
            f.write("outside the web directory")
        os.symlink(os.path.join(cls.tmp, "outside.txt"), os.path.join(cls.web, "escape.txt"))
        # A three.js directory laid out as Debian's libjs-three: build/three.module.js a relative symlink to the file
        # beside build/ (allowed: it stays inside the directory), an addon under examples/jsm/.
        cls.three = os.path.join(cls.tmp, "three")
        os.makedirs(os.path.join(cls.three, "build"))
        os.makedirs(os.path.join(cls.three, "examples", "jsm", "controls"))
        with open(os.path.join(cls.three, "three.module.js"), "w") as f:
            f.write("export const REVISION = 'test';\n")
        os.symlink("../three.module.js", os.path.join(cls.three, "build", "three.module.js"))
        with open(os.path.join(cls.three, "examples", "jsm", "controls", "Orbit.js"), "w") as f:
            f.write('import { REVISION } from "../../../build/three.module.js";\n')
        os.symlink(os.path.join(cls.tmp, "outside.txt"), os.path.join(cls.three, "escape.js"))
        # The page's own vendor/three/ is hidden by the mount: never served, even for a file the mount lacks.
        os.makedirs(os.path.join(cls.web, "vendor", "three"))
        with open(os.path.join(cls.web, "vendor", "three", "shadowed.js"), "w") as f:
            f.write("the page's own copy")
        cls.server = h.Server(args=["--web-dir", cls.web, "--three-dir", cls.three, "--auth-token", "s3cret"])

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_index_and_assets(self):
        r = self.server.request("GET", "/")
        self.assertEqual(r.status, 200)
        self.assertEqual(r.header("Content-Type"), "text/html; charset=utf-8")
        self.assertEqual(r.header("Cache-Control"), "no-cache")
        self.assertIn(b"<title>page</title>", r.body)
        r = self.server.request("GET", "/vendor/lib.js")
        self.assertEqual(r.status, 200)
        self.assertEqual(r.header("Content-Type"), "text/javascript; charset=utf-8")
        self.assertEqual(r.body, b"export const x = 1;\n")

    def test_three_js_from_its_own_directory(self):
        r = self.server.request("GET", "/vendor/three/build/three.module.js")
        self.assertEqual(r.status, 200)
        self.assertEqual(r.header("Content-Type"), "text/javascript; charset=utf-8")
        self.assertEqual(r.body, b"export const REVISION = 'test';\n")
        r = self.server.request("GET", "/vendor/three/examples/jsm/controls/Orbit.js")
        self.assertEqual(r.status, 200)
        self.assertIn(b"../../../build/three.module.js", r.body)
        for path in ["/vendor/three/shadowed.js", "/vendor/three/escape.js", "/vendor/three/../outside.txt",
                     "/vendor/three/", "/vendor/three/.hidden", "/vendor/three/build/../../outside.txt"]:
            r = self.server.request("GET", path)
            self.assertEqual(r.status, 404, path)
            self.assertNotIn(b"outside the web directory", r.body)
            self.assertNotIn(b"the page's own copy", r.body)

    def test_page_loads_without_token_but_api_needs_it(self):
        self.assertEqual(self.server.request("GET", "/").status, 200)
        self.assertEqual(self.server.request("GET", "/v1/models").status, 401)
        r = self.server.request("GET", "/v1/models", headers={"Authorization": "Bearer s3cret"})
        self.assertEqual(r.status, 200)

    def test_nothing_outside_the_directory_or_hidden(self):
        for path in ["/../outside.txt", "/vendor/../../outside.txt", "/%2e%2e/outside.txt", "/escape.txt",
                     "/.secret", "/vendor//lib.js", "/missing.js", "/vendor/", "/..%2foutside.txt"]:
            r = self.server.request("GET", path)
            self.assertEqual(r.status, 404, path)
            body = r.json()
            h.validate("Error", body)
            self.assertNotIn(b"outside the web directory", r.body)

    def test_api_routes_still_win(self):
        r = self.server.request("GET", "/openapi.json")
        self.assertEqual(r.status, 200)
        self.assertEqual(r.json(), h.OPENAPI)
        self.assertEqual(self.server.request("GET", "/healthz").status, 200)


THREE_DIR = "/usr/share/javascript/three"


@unittest.skipIf(SKIP, SKIP or "")
@unittest.skipUnless(os.path.isfile(os.path.join(THREE_DIR, "build", "three.module.js")),
                     "Debian's libjs-three is not installed (scripts/install-deps.sh installs it)")
class DefaultPageTest(unittest.TestCase):
    """The page as `wish serve` serves it without web flags: web/src as it is (no build step) and the three.js of
    Debian's libjs-three. Every module the page imports resolves, and three.js is loaded from one URL only."""

    @classmethod
    def setUpClass(cls):
        cls.server = h.Server()

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)

    def fetch(self, url_path):
        r = self.server.request("GET", url_path)
        self.assertEqual(r.status, 200, url_path)
        return r.body.decode()

    def test_every_import_resolves_and_three_is_loaded_once(self):
        index = self.fetch("/")
        imports = json.loads(re.search(r'<script type="importmap">(.*?)</script>', index, re.S).group(1))["imports"]
        self.assertEqual(imports["three"], "./vendor/three/build/three.module.js")

        def resolve(specifier, importer):
            for key, target in sorted(imports.items(), key=lambda kv: -len(kv[0])):
                if specifier == key or (key.endswith("/") and specifier.startswith(key)):
                    return posixpath.normpath("/" + target[len("./"):] + specifier[len(key):])
            self.assertTrue(specifier.startswith("."), "bare specifier without a mapping: " + specifier)
            return posixpath.normpath(posixpath.join(posixpath.dirname(importer), specifier))

        three = resolve("three", "/index.html")
        # Breadth-first over the page's modules; the three.js files are followed as well.
        seen, pending, three_urls = set(), ["/app.js"], set()
        while pending:
            url = pending.pop()
            if url in seen:
                continue
            seen.add(url)
            text = self.fetch(url)
            for specifier in re.findall(r'(?:^|\n)\s*(?:import|export)\b[^;]*?from\s*["\']([^"\']+)["\']', text):
                target = resolve(specifier, url)
                if target.endswith("/three.module.js"):
                    three_urls.add(target)
                pending.append(target)
        self.assertIn("/viewer.js", seen)
        self.assertIn("/vendor/three/examples/jsm/controls/OrbitControls.js", seen)
        # OrbitControls imports three.js by a relative path: it must be the import map's URL, or the browser would
        # load a second three.js.
        self.assertEqual(three_urls, {three})
        self.assertRegex(self.fetch(three), r"REVISION = '\d+'")


@unittest.skipIf(SKIP, SKIP or "")
class NoWebDirTest(unittest.TestCase):
    def test_without_web_dir_the_root_is_404(self):
        with h.Server(args=["--web-dir", ""]) as server:
            r = server.request("GET", "/")
            self.assertEqual(r.status, 404)
            h.validate("Error", r.json())


if __name__ == "__main__":
    unittest.main()
