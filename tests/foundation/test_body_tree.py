"""Walks up a MuJoCo body tree: ancestors and subtree membership on a small hand-built tree."""

import mujoco

from eigengait.body_tree import ancestors, in_subtree

TREE = """
<mujoco>
  <worldbody>
    <body name="root"><freejoint/><geom size="0.1"/>
      <body name="thigh"><joint type="ball"/><geom size="0.1"/>
        <body name="shin"><joint type="hinge"/><geom size="0.1"/></body>
      </body>
      <body name="arm"><joint type="ball"/><geom size="0.1"/></body>
    </body>
    <body name="post"><geom size="0.1"/></body>
  </worldbody>
</mujoco>
"""


def test_ancestors_and_subtrees_follow_the_parents():
    model = mujoco.MjModel.from_xml_string(TREE)
    body = {name: model.body(name).id for name in ("root", "thigh", "shin", "arm", "post")}
    assert list(ancestors(model, body["shin"])) == [body["shin"], body["thigh"], body["root"]]
    assert list(ancestors(model, 0)) == []  # the world has none
    assert in_subtree(model, body["shin"], body["thigh"])
    assert in_subtree(model, body["thigh"], body["thigh"])
    assert not in_subtree(model, body["arm"], body["thigh"])
    assert not in_subtree(model, body["post"], body["root"])
    assert not in_subtree(model, body["shin"], 0)  # the world is no body's subtree root
