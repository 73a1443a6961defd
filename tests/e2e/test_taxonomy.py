"""The taxonomy file, offline and mirrored into the real store."""
from __future__ import annotations

from sg3d.ingest.discover import furniture
from sg3d.queries import taxonomy
from sg3d.queries.taxonomy import Taxonomy

COCO80 = {
    "person", "bicycle", "car", "motorcycle", "airplane", "bus", "train", "truck", "boat",
    "traffic light", "fire hydrant", "stop sign", "parking meter", "bench", "bird", "cat", "dog",
    "horse", "sheep", "cow", "elephant", "bear", "zebra", "giraffe", "backpack", "umbrella",
    "handbag", "tie", "suitcase", "frisbee", "skis", "snowboard", "sports ball", "kite",
    "baseball bat", "baseball glove", "skateboard", "surfboard", "tennis racket", "bottle",
    "wine glass", "cup", "fork", "knife", "spoon", "bowl", "banana", "apple", "sandwich", "orange",
    "broccoli", "carrot", "hot dog", "pizza", "donut", "cake", "chair", "couch", "potted plant",
    "bed", "dining table", "toilet", "tv", "laptop", "mouse", "remote", "keyboard", "cell phone",
    "microwave", "oven", "toaster", "sink", "refrigerator", "book", "clock", "vase", "scissors",
    "teddy bear", "hair drier", "toothbrush",
}
# what sg3d names from an object's shape where no COCO class fits
BY_SHAPE = {furniture.DESK_LABEL, furniture.CABINET_LABEL}


def test_every_coco_class_is_a_leaf_reaching_the_root():
    tax = Taxonomy.load()
    assert len(COCO80) == 80
    assert tax.leaves == COCO80 | BY_SHAPE
    for label in COCO80 | BY_SHAPE:
        assert tax.ancestors(label)[-1] == "object", label


def test_required_groups_and_members():
    tax = Taxonomy.load()
    assert tax.labels_under("furniture") == {"chair", "couch", "bed", "dining table", "toilet", "bench"} | BY_SHAPE
    assert tax.labels_under("tableware") == {"cup", "bowl", "wine glass", "bottle"}
    assert tax.labels_under("cutlery") == {"fork", "knife", "spoon"}
    assert tax.labels_under("electronics") == {"tv", "laptop", "mouse", "remote", "keyboard", "cell phone"}
    assert tax.labels_under("appliance") == {"microwave", "oven", "toaster", "sink", "refrigerator"}
    assert {"banana", "apple"} <= tax.labels_under("food")
    assert tax.parent("cup") == "tableware" and tax.is_a("fork", "kitchenware")
    assert tax.labels_under("object") == COCO80 | BY_SHAPE


def test_store_mirror_is_idempotent_and_matches_offline(store):
    taxonomy.forget()
    assert taxonomy.ensure_taxonomy(store) is True
    assert taxonomy.ensure_taxonomy(store) is False          # cached in process
    taxonomy.forget()
    assert taxonomy.ensure_taxonomy(store) is False          # version marker matches
    tax = Taxonomy.load()
    n = store.run_raw("MATCH (c:Category) RETURN count(c) AS n")[1][0][0]
    e = store.run_raw("MATCH (:Category)-[r:IS_A]->(:Category) RETURN count(r) AS n")[1][0][0]
    assert n == len(tax.names) and e == len(tax.parents)
    assert taxonomy.ensure_taxonomy(store, force=True) is True
    e2 = store.run_raw("MATCH (:Category)-[r:IS_A]->(:Category) RETURN count(r) AS n")[1][0][0]
    assert e2 == e
    assert taxonomy.descendants(store, "kitchenware") == tax.descendants("kitchenware")
    assert taxonomy.descendants(store, "cup") == {"cup"}
    assert taxonomy.ancestors(store, "fork") == ["cutlery", "kitchenware", "object"]


def test_descendants_reload_after_a_wipe(store):
    taxonomy.ensure_taxonomy(store)
    store.wipe()
    assert taxonomy.descendants(store, "cutlery") == {"cutlery", "fork", "knife", "spoon"}
