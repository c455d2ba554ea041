# The Python side of bullet_sim: the sweep tool's package (catkin_python_setup installs it).
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["bullet_sim_sweep"], package_dir={"": "python"}))
