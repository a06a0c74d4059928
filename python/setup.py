# Only what pyproject.toml cannot say: the wheel carries a compiled plugin, so it is tagged for
# this platform (linux_x86_64) instead of "any". It holds no Python extension, so one wheel
# serves every Python 3 that pymeshlab 2025.7.post1 supports (tag py3-none).
from setuptools import setup
from setuptools.dist import Distribution

try:
    from wheel.bdist_wheel import bdist_wheel
except ImportError:  # wheel >= 0.44 moved it into setuptools
    from setuptools.command.bdist_wheel import bdist_wheel


class BinaryDistribution(Distribution):
    def has_ext_modules(self):
        return True


class PlatformWheel(bdist_wheel):
    def get_tag(self):
        _, _, platform = super().get_tag()
        return "py3", "none", platform


setup(distclass=BinaryDistribution, cmdclass={"bdist_wheel": PlatformWheel})
