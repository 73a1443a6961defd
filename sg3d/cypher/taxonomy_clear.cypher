// Drop the IS_A edges before a (re)load, so a changed taxonomy leaves no stale parent behind.
MATCH (:Category)-[e:IS_A]->(:Category)
DELETE e
