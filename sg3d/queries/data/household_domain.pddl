; Household manipulation for a one-arm mobile robot, planned from a 3-D scene graph (sg3d).
; Plain typed STRIPS on purpose: pyperplan supports nothing more, so every "not" a precondition
; would need is a positive twin predicate instead (handempty/holding, opened/closed).
(define (domain household)
  (:requirements :strips :typing)
  (:types
    location item agent - object
    surface receptacle - location)   ; a place the robot drives to; surfaces hold things ON them, receptacles IN them

  (:predicates
    (at ?r - agent ?l - location)
    (handempty ?r - agent)
    (holding ?r - agent ?i - item)
    (on ?i - item ?s - surface)
    (in ?i - item ?c - receptacle)
    (opened ?c - receptacle)          ; doorless receptacles (a sink) are opened and stay so
    (closed ?c - receptacle)
    (has-door ?c - receptacle))       ; static: only these may be closed again

  (:action navigate
    :parameters (?r - agent ?from - location ?to - location)
    :precondition (at ?r ?from)
    :effect (and (at ?r ?to) (not (at ?r ?from))))

  (:action pick
    :parameters (?r - agent ?i - item ?s - surface)
    :precondition (and (at ?r ?s) (on ?i ?s) (handempty ?r))
    :effect (and (holding ?r ?i) (not (on ?i ?s)) (not (handempty ?r))))

  (:action place
    :parameters (?r - agent ?i - item ?s - surface)
    :precondition (and (at ?r ?s) (holding ?r ?i))
    :effect (and (on ?i ?s) (handempty ?r) (not (holding ?r ?i))))

  (:action take-out
    :parameters (?r - agent ?i - item ?c - receptacle)
    :precondition (and (at ?r ?c) (in ?i ?c) (opened ?c) (handempty ?r))
    :effect (and (holding ?r ?i) (not (in ?i ?c)) (not (handempty ?r))))

  (:action put-in
    :parameters (?r - agent ?i - item ?c - receptacle)
    :precondition (and (at ?r ?c) (holding ?r ?i) (opened ?c))
    :effect (and (in ?i ?c) (handempty ?r) (not (holding ?r ?i))))

  (:action open
    :parameters (?r - agent ?c - receptacle)
    :precondition (and (at ?r ?c) (closed ?c) (has-door ?c) (handempty ?r))
    :effect (and (opened ?c) (not (closed ?c))))

  (:action close
    :parameters (?r - agent ?c - receptacle)
    :precondition (and (at ?r ?c) (opened ?c) (has-door ?c) (handempty ?r))
    :effect (and (closed ?c) (not (opened ?c))))
)
