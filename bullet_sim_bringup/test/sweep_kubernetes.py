#!/usr/bin/env python3
"""The Kubernetes recipe, bullet_sim/deploy/kubernetes/scenario_matrix_job.yaml: each of its objects validates
against the schemas that PyPI's kubernetes-validate bundles, strictly (an unknown field fails), from Kubernetes
1.29 (the first with backoffLimitPerIndex) to the newest bundled; the Job has a completion per cell of its
matrix; and its container's command, run here as the Job's pods run it for a few JOB_COMPLETION_INDEX values (the
container's environment, with the image's paths replaced by this workspace's), writes those cells' results."""
import copy
import json
import os
import subprocess
import tempfile
import unittest

import kubernetes_validate
import rospkg
import rostest
import yaml
from kubernetes_validate.utils import latest_version

PACKAGE = rospkg.RosPack().get_path("bullet_sim")
RECIPE = os.path.join(PACKAGE, "deploy/kubernetes/scenario_matrix_job.yaml")
OLDEST = "1.29.0"
INDEXES = [0, 7, 19]
RUN_TIMEOUT = 60  # [s] per cell


def devel_space():
    """This workspace's devel space: the first CMAKE_PREFIX_PATH entry with a setup.bash."""
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(":"):
        if os.path.isfile(os.path.join(prefix, "setup.bash")):
            return prefix
    raise RuntimeError("no devel space on CMAKE_PREFIX_PATH: source devel/setup.bash")


class KubernetesRecipe(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(RECIPE) as file:
            cls.objects = list(yaml.safe_load_all(file))
        cls.job = next(o for o in cls.objects if o["kind"] == "Job")
        cls.container = cls.job["spec"]["template"]["spec"]["containers"][0]

    def test_its_objects_validate_against_the_kubernetes_schemas(self):
        self.assertEqual([o["kind"] for o in self.objects], ["PersistentVolumeClaim", "Job"])
        for version in (OLDEST, latest_version()):
            for manifest in self.objects:
                kubernetes_validate.validate(manifest, version, strict=True)
        # The validator refuses what Kubernetes would: a misspelt field, a field newer than the version.
        misspelt = copy.deepcopy(self.job)
        misspelt["spec"]["completion"] = misspelt["spec"].pop("completions")
        with self.assertRaises(kubernetes_validate.ValidationError):
            kubernetes_validate.validate(misspelt, latest_version(), strict=True)
        with self.assertRaises(kubernetes_validate.ValidationError):
            kubernetes_validate.validate(self.job, "1.27.0", strict=True)

    def test_its_command_runs_the_cells_of_its_indexes(self):
        folder = tempfile.mkdtemp(prefix="sweep_kubernetes_")
        matrix = os.path.join(PACKAGE, "scenarios", os.path.basename(self.container_env()["MATRIX"]))
        listed = subprocess.run(["rosrun", "bullet_sim", "scenario", "--matrix", matrix, "--list"],
                                capture_output=True, text=True, timeout=RUN_TIMEOUT, check=True)
        cells = json.loads(listed.stdout)["cells"]
        self.assertEqual(self.job["spec"]["completions"], len(cells))
        for index in INDEXES:
            # As a pod: a clean environment, the container's, and the index Kubernetes gives it.
            env = dict(self.container_env(), DEVEL=devel_space(), MATRIX=matrix, RESULTS=folder,
                       JOB_COMPLETION_INDEX=str(index), PATH="/usr/bin:/bin", HOME=os.environ["HOME"])
            run = subprocess.run(self.container["command"] + self.container["args"], env=env, capture_output=True,
                                 text=True, timeout=RUN_TIMEOUT)
            with open(os.path.join(folder, str(index), "result.json")) as file:
                result = json.load(file)
            self.assertEqual(run.returncode, result["exit_code"], run.stdout + run.stderr)
            self.assertIn(result["verdict"], ("pass", "fail"), run.stdout + run.stderr)
            self.assertEqual(result["matrix"]["index"], index)
            self.assertEqual(result["matrix"]["values"], cells[index]["values"])
            self.assertTrue(os.path.isfile(os.path.join(folder, str(index), "trajectory.csv")))

    def container_env(self):
        return {variable["name"]: variable["value"] for variable in self.container["env"]}


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "sweep_kubernetes", KubernetesRecipe)
