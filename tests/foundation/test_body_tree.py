"""Walks up a MuJoCo body tree: ancestors, subtree membership and a limb's own joints on small
hand-built trees."""

import mujoco

from eigengait.body_tree import ancestors, in_subtree, limb_dofs

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


CHEST_ROOT = """
<mujoco>
  <worldbody>
    <body name="chest"><freejoint/><geom size="0.1"/>
      <body name="pelvis"><joint type="hinge"/><joint type="hinge" axis="1 0 0"/><geom size="0.1"/>
        <body name="left_thigh"><joint type="ball"/><geom size="0.1"/>
          <body name="left_foot"><joint type="hinge"/><geom size="0.1"/></body>
        </body>
        <body name="right_thigh"><joint type="ball"/><geom size="0.1"/>
          <body name="right_foot"><joint type="hinge"/><geom size="0.1"/></body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_a_limb_stops_where_another_limb_joins_it():
    # the free root is the chest (dm_control's suite humanoid): the pelvis's two hinges move
    # both feet, so they belong to neither leg; a lone limb runs up to the world
    model = mujoco.MjModel.from_xml_string(CHEST_ROOT)
    left, right = model.body("left_foot").id, model.body("right_foot").id
    thigh = model.body("left_thigh").id
    own = [d for d in range(model.nv) if model.dof_bodyid[d] in (thigh, left)]
    assert limb_dofs(model, left, [right]) == own == list(range(8, 12))
    assert limb_dofs(model, left, []) == list(range(model.nv - 4))
