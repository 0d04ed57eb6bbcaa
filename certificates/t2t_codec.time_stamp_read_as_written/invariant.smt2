; atcs proof certificate: t2t_codec.time_stamp_read_as_written (T2T-06), k = 0
; check: invariant; expected: unsat
(set-logic ALL)
(set-info :status unknown)
(declare-fun speed_mps@0 () Real)
(declare-fun rear_m@0 () Real)
(declare-fun sent_s@0 () Real)
(declare-fun seq@0 () Real)
(declare-fun sender_id@0 () Real)
(assert
 true)
(assert
 (let ((?x21 (to_real (to_int (* speed_mps@0 100.0)))))
 (let (($x84 (and (= (to_real (to_int ?x21)) ?x21) (<= 0.0 ?x21) (>= 65535.0 ?x21))))
 (let ((?x18 (to_real (to_int (* rear_m@0 100.0)))))
 (let (($x78 (and (= (to_real (to_int ?x18)) ?x18) (<= (- 2147483648.0) ?x18) (>= 2147483647.0 ?x18))))
 (let ((?x15 (to_real (to_int (* sent_s@0 1000.0)))))
 (let (($x71 (and (= (to_real (to_int ?x15)) ?x15) (<= 0.0 ?x15) (>= 4294967295.0 ?x15))))
 (let (($x66 (and (= (to_real (to_int seq@0)) seq@0) (<= 0.0 seq@0) (>= 4294967295.0 seq@0))))
 (let (($x60 (and (= (to_real (to_int sender_id@0)) sender_id@0) (<= 0.0 sender_id@0) (>= 16777215.0 sender_id@0))))
 (let (($x85 (and $x60 $x66 $x71 $x78 $x84)))
 (and $x85)))))))))))
(assert
 true)
(assert
 (let ((?x51 (/ (to_real (mod (to_int (to_real (to_int (* sent_s@0 1000.0)))) 4294967296)) 1000.0)))
 (= ?x51 (/ (to_real (to_int (* sent_s@0 1000.0))) 1000.0))))
(assert
 (let ((?x51 (/ (to_real (mod (to_int (to_real (to_int (* sent_s@0 1000.0)))) 4294967296)) 1000.0)))
(let (($x88 (= ?x51 (/ (to_real (to_int (* sent_s@0 1000.0))) 1000.0))))
(not $x88))))
(check-sat)
