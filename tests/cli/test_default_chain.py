"""One chain by default (issue 37 item 2): `wish describe` and `wish map` with no options run the default training
recipe's map (core/pipeline/default_pipeline_options.hpp): the cMCF chain, then the canonical isometric relaxation,
and describe fits at the recipe's Lmax. `wish map` writes the map `wish describe` computes its descriptor on, and the
paper's settings printed by `wish describe --help` give the paper's map back.
"""
import json
import os
import re
import tempfile
import unittest

from wish_cli import SOURCE_DIR, run

MESH = os.path.join(SOURCE_DIR, "data", "meshes", "celegans_cell.obj")


def recipe_value(field):
    with open(os.path.join(SOURCE_DIR, "core", "classify", "default_recipe.cpp")) as f:
        return re.search(r"recipe\.%s = ([^;]+);" % re.escape(field), f.read()).group(1)


class DefaultChain(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-default-chain-")
        cls.described = json.loads(run("describe", MESH, "--json").stdout)[0]
        sphere = os.path.join(cls.tmp, "sphere.ply")
        cls.mapped = json.loads(run("map", MESH, "--out", sphere, "--json").stdout)

    def test_describe_defaults_to_the_training_recipe(self):
        self.assertEqual(self.described["descriptor"]["lmax"], int(recipe_value("sh.lmax")))
        self.assertEqual(self.described["map"]["canonical"]["method"], "isometric")
        self.assertEqual(recipe_value("map.canonical.method"), "CanonicalMap::Isometric")

    def test_map_and_describe_end_on_the_same_map(self):
        self.assertEqual(self.mapped["method"], self.described["map"]["method"])
        self.assertEqual(self.mapped["canonical"]["method"], self.described["map"]["canonical"]["method"])
        self.assertEqual(self.mapped["canonical"]["iterations"], self.described["map"]["canonical"]["iterations"])
        self.assertAlmostEqual(self.mapped["canonical"]["energy"], self.described["map"]["canonical"]["energy"], places=9)

    def test_the_papers_settings_from_help_give_the_papers_map(self):
        help_text = run("describe", "--help").stdout
        paper = re.search(r"--method (\w+) --canonical (\w+) --lmax (\d+) --regularization (\S+)\.", help_text)
        self.assertIsNotNone(paper, help_text)
        r = json.loads(run("describe", MESH, "--json", "--method", paper.group(1), "--canonical", paper.group(2),
                           "--lmax", paper.group(3), "--regularization", paper.group(4)).stdout)[0]
        self.assertEqual(r["map"]["method"], "willmore")
        self.assertNotIn("canonical", r["map"])
        self.assertEqual(r["descriptor"]["lmax"], int(paper.group(3)))


if __name__ == "__main__":
    unittest.main()
