"""The package's own files and folders, below everything else (they import nothing of the
package, so that any part may use them without an import cycle):

* ``packagedata``: where the shipped data folders (assets, examples) are;
* ``outdir``: a results folder that is either complete or absent, never over the user's files;
* ``mjlog``: MuJoCo's warnings as Python warnings, never a ``MUJOCO_LOG.TXT`` in the working folder.
"""
