"""`wish train --lmax` and `wish describe --lmax` take core's range (issue 37 item 5): features start at degree 1
(core/classify/feature_pipeline.hpp kMinFeatureLmax), the SH fit stops at 64 (core/sh/sh_lmax_range.hpp
kShMaxFitLmax). Out of range is refused by the command line, with the range in the message, before any input is read.
"""
import os
import re
import unittest

from wish_cli import SOURCE_DIR, run


def core_constant(relative_path, name):
    with open(os.path.join(SOURCE_DIR, relative_path)) as f:
        return int(re.search(r"constexpr int %s = (\d+);" % name, f.read()).group(1))


MIN_FEATURE_LMAX = core_constant("core/classify/feature_pipeline.hpp", "kMinFeatureLmax")
MIN_FIT_LMAX = core_constant("core/sh/sh_lmax_range.hpp", "kShMinFitLmax")
MAX_FIT_LMAX = core_constant("core/sh/sh_lmax_range.hpp", "kShMaxFitLmax")


class LmaxBounds(unittest.TestCase):
    def refused(self, *args):
        # The input does not exist: a run that got past the option check would fail on it with another message.
        p = run(*args, check=False)
        self.assertNotEqual(p.returncode, 0, p.stdout)
        self.assertIn("--lmax", p.stderr)
        return p.stderr

    def test_train_refuses_lmax_above_the_fits_limit(self):
        err = self.refused("train", "no-such-input.csv", "--lmax", str(MAX_FIT_LMAX + 1))
        self.assertIn("%d to %d" % (MIN_FEATURE_LMAX, MAX_FIT_LMAX), err)

    def test_train_refuses_lmax_zero(self):
        err = self.refused("train", "no-such-input.csv", "--lmax", "0")
        self.assertIn("%d to %d" % (MIN_FEATURE_LMAX, MAX_FIT_LMAX), err)

    def test_train_takes_the_bounds_themselves(self):
        # Past the option check, the run stops at the missing input, not at --lmax.
        for lmax in (MIN_FEATURE_LMAX, MAX_FIT_LMAX):
            p = run("train", "no-such-input.csv", "--lmax", str(lmax), check=False)
            self.assertNotEqual(p.returncode, 0)
            self.assertIn("no-such-input.csv", p.stderr)
            self.assertNotIn("not in range", p.stderr)

    def test_describe_refuses_lmax_above_the_fits_limit(self):
        err = self.refused("describe", "no-such-mesh.off", "--lmax", str(MAX_FIT_LMAX + 1))
        self.assertIn("%d to %d" % (MIN_FIT_LMAX, MAX_FIT_LMAX), err)


if __name__ == "__main__":
    unittest.main()
