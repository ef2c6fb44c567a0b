# The participant's side of lockstep for Python nodes and test scripts (catkin_python_setup).
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=['lockstep'], package_dir={'': 'src'}))
